// The generator graph of a SkyProcessor (private to the engine): which generators run, in which
// order, and the checks that make the order well defined.
//
//   GeneratorGraph graph;
//   graph.add(std::make_shared<astro::AstronomyGenerator>(), vars);  // processor-level, declares its keys
//   graph.order(vars, elements, optionsSet);   // throws naming the generators on a conflict or a cycle
//   graph.run(vars, log, /*timing=*/false, /*validation=*/false);    // each due generator once
//
// The nodes are every generator once: the processor-level ones in registration order, then each
// element's (an instance shared by several elements counts once). An edge goes from the one
// generator that writes a key to every generator that reads it. The order is Kahn's algorithm
// taking the earliest-registered ready generator each time, so it is stable: independent
// generators keep their registration order. Which generator is due (an input's version or value
// changed since its last run) is the generator's own bookkeeping (Generator::isDue()); the graph
// only decides the order in which they are asked.
#pragma once
#include <welkin/element.hpp>
#include <welkin/log.hpp>
#include <welkin/vars.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace welkin {

class GeneratorGraph {
public:
    /// Registers a processor-level generator once (the same instance again is ignored) and lets
    /// it declare its keys in `vars`, named as their declarer. Throws welkin::Error for null.
    void add(std::shared_ptr<Generator> generator, SkyVars& vars);
    /// The order is rebuilt by the next order() (a generator or an element was added); the old
    /// one stays readable (and released by release()) until then.
    void invalidate() { valid_ = false; }
    /// Invalidates and forgets the old order too (an element was removed: its generators may be gone).
    void forgetOrder() {
        order_.clear();
        valid_ = false;
    }
    bool valid() const { return valid_; }

    /// Orders every generator (the processor's, then each element's of `elements`), after letting
    /// each declare its keys. Throws welkin::Error ("SkyProcessor::init(): ...") if two generators
    /// write one key, a key in `optionsSet` (set by the host with setOption()) is a generator's
    /// output or an element's written key, a generator reads a key that nobody declares or writes
    /// (unless the input is optional), or the dependencies form a cycle.
    void order(SkyVars& vars, const std::vector<std::unique_ptr<SkyElement>>& elements, const std::vector<std::string>& optionsSet);
    /// The generators in the order they run (valid after order()).
    const std::vector<Generator*>& ordered() const { return order_; }

    /// Runs each generator in order if it is due; `timing` brackets each with glFinish,
    /// `validation` checks GL errors after each (throws welkin::Error naming the generator).
    void run(SkyVars& vars, const Logger& log, bool timing, bool validation);

    /// Frees every generator's GL resources (context current) and invalidates the order: the next
    /// frame orders and runs them again.
    void release();

    /// Throws welkin::Error if `key` is an output of one of the processor's generators
    /// (generatorOutputMessage), or of an element's generator or written by the element
    /// (elementOutputMessage), checked element by element in order: setOption()'s check.
    void checkNotAnOutput(std::string_view key, const std::vector<std::unique_ptr<SkyElement>>& elements) const;

private:
    std::vector<std::shared_ptr<Generator>> own_;  // processor-level, registration order
    std::vector<Generator*> order_;
    bool valid_ = false;
};

/// "<key> is an output of the generator '<name>', not an input (...)": setOption()'s message.
std::string generatorOutputMessage(std::string_view key, const Generator& g);
/// "<key> is written by the element '<name>' every frame, not an input".
std::string elementOutputMessage(std::string_view key, const SkyElement& e);

}  // namespace welkin
