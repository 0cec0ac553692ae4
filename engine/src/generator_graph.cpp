// The generator graph (generator_graph.hpp): registration, ordering by inputs and outputs, runs.
#include "generator_graph.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/objects.hpp>

#include <algorithm>
#include <map>

namespace welkin {

std::string generatorOutputMessage(std::string_view key, const Generator& g) {
    return std::string(key) + " is an output of the generator '" + g.name() +
           "', not an input (it is computed every frame from the time, the place and the generator's inputs: `welkin vars` lists them)";
}

std::string elementOutputMessage(std::string_view key, const SkyElement& e) {
    return std::string(key) + " is written by the element '" + e.name() + "' every frame, not an input";
}

void GeneratorGraph::add(std::shared_ptr<Generator> g, SkyVars& vars) {
    if (!g) throw Error("SkyProcessor::addGenerator(): null generator");
    for (auto& existing : own_)
        if (existing == g) return;
    SkyVars::DeclarerScope scope(vars, g->name());
    g->declareKeys(vars);
    own_.push_back(std::move(g));
    valid_ = false;
}

void GeneratorGraph::checkNotAnOutput(std::string_view key, const std::vector<std::unique_ptr<SkyElement>>& elements) const {
    auto check = [&](const Generator& g) {
        for (const KeyInfo& k : g.outputs())
            if (k.name == key) throw Error(generatorOutputMessage(key, g));
    };
    for (auto& g : own_) check(*g);
    for (auto& e : elements) {
        for (auto& g : e->generators()) check(*g);
        for (const KeyInfo& k : e->writeKeys())
            if (k.name == key) throw Error(elementOutputMessage(key, *e));
    }
}

void GeneratorGraph::order(SkyVars& vars, const std::vector<std::unique_ptr<SkyElement>>& elements,
                           const std::vector<std::string>& optionsSet) {
    // Every generator once: the processor's, then each element's (shared instances deduplicated).
    std::vector<Generator*> all;
    auto addUnique = [&](Generator* g) {
        if (std::find(all.begin(), all.end(), g) == all.end()) all.push_back(g);
    };
    for (auto& g : own_) addUnique(g.get());
    for (auto& e : elements)
        for (auto& g : e->generators()) addUnique(g.get());
    for (Generator* g : all) {
        SkyVars::DeclarerScope scope(vars, g->name());
        g->declareKeys(vars);
    }
    // Writers: one per key.
    std::map<std::string, size_t> writer;
    for (size_t i = 0; i < all.size(); ++i)
        for (const KeyInfo& k : all[i]->outputs()) {
            auto [it, inserted] = writer.emplace(k.name, i);
            if (!inserted && it->second != i)
                throw Error("SkyProcessor::init(): key '" + k.name + "' is written by two generators, '" + all[it->second]->name() +
                            "' and '" + all[i]->name() + "'");
        }
    // A key the caller set with setOption() must not be a generator's output (an element's
    // generators are attached at its init(), after the option was set).
    for (const std::string& k : optionsSet)
        if (auto it = writer.find(k); it != writer.end()) throw Error(generatorOutputMessage(k, *all[it->second]));
    for (auto& e : elements)
        for (const KeyInfo& w : e->writeKeys())
            if (std::find(optionsSet.begin(), optionsSet.end(), w.name) != optionsSet.end()) throw Error(elementOutputMessage(w.name, *e));
    // Reads: of a key some generator writes (an edge), or of a declared key, or optional.
    std::vector<std::vector<size_t>> after(all.size());  // after[w] = readers of w's outputs
    std::vector<int> pending(all.size(), 0);
    for (size_t i = 0; i < all.size(); ++i) {
        const auto& ins = all[i]->inputs();
        std::vector<size_t> deps;
        for (size_t k = 0; k < ins.size(); ++k) {
            auto it = writer.find(ins[k].name);
            if (it != writer.end()) {
                if (it->second != i && std::find(deps.begin(), deps.end(), it->second) == deps.end()) deps.push_back(it->second);
                continue;
            }
            if (!vars.contains(ins[k].name) && !all[i]->inputOptions(k).optional)
                throw Error("SkyProcessor::init(): generator '" + all[i]->name() + "' reads key '" + ins[k].name +
                            "', which no element, generator or host declares");
        }
        for (size_t d : deps) after[d].push_back(i);
        pending[i] = int(deps.size());
    }
    // Kahn's algorithm, always taking the earliest-registered ready generator (stable order).
    std::vector<Generator*> order;
    std::vector<bool> done(all.size(), false);
    while (order.size() < all.size()) {
        size_t pick = all.size();
        for (size_t i = 0; i < all.size(); ++i)
            if (!done[i] && pending[i] == 0) {
                pick = i;
                break;
            }
        if (pick == all.size()) {
            std::string cycle;
            for (size_t i = 0; i < all.size(); ++i)
                if (!done[i]) cycle += (cycle.empty() ? "" : ", ") + all[i]->name();
            throw Error("SkyProcessor::init(): generators depend on each other in a cycle: " + cycle);
        }
        done[pick] = true;
        order.push_back(all[pick]);
        for (size_t r : after[pick]) --pending[r];
    }
    order_ = std::move(order);
    valid_ = true;
}

void GeneratorGraph::run(SkyVars& vars, const Logger& log, bool timing, bool validation) {
    for (Generator* g : order_) {
        g->runIfDue(vars, log, timing);
        if (validation) gl::checkError(g->name() + "::run()");
    }
}

void GeneratorGraph::release() {
    // Generators own GL resources too (LUTs); released and invalidated so that init() and the
    // next frame make them again.
    for (Generator* g : order_) g->release();
    for (auto& g : own_) g->release();
    order_.clear();
    valid_ = false;
}

}  // namespace welkin
