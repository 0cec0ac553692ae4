// welkin vars: every SkyVars key of a scene with all known elements: type, unit, range, default,
// description, who declares it, and the elements and generators that read or write it.
#include "command.hpp"

#include <welkin/element.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/processor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

namespace welkin::cli {

namespace {

struct VarsOptions {
    bool json = false;
    bool markdown = false;
    std::string elements;
};

struct Row {
    KeyInfo info;
    std::string declarer, value;
    std::set<std::string> options, readers, writers;
};

// "enum" for a string key with named values, else the value type's name.
std::string typeText(const KeyInfo& k) { return k.choices.empty() ? std::string(k.typeName) : std::string("enum"); }

std::string rangeText(const std::optional<Range>& r) {
    if (!r) return "";
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%g, %g]", r->min, r->max);
    return buf;
}

template <class Strings>
std::string join(const Strings& s) {
    std::string out;
    for (auto& x : s) out += (out.empty() ? "" : ", ") + x;
    return out;
}

int run(const VarsOptions& o) {
    Logger log;
    std::vector<std::string> names = o.elements.empty() ? elements::knownElements() : elements::expandElementList(o.elements);
    auto ctx = gl::HeadlessContext::create({}, log);
    std::map<std::string, Row> rows;
    {
        SkyProcessor p(SkyVars::earth(), log);
        for (auto& n : names) p.add(elements::makeElement(n));
        p.init();  // elements declare their keys and attach their generators; the graph is checked
        for (const KeyDescription& d : p.vars().describe()) {
            if (d.info.typeName == std::string("object")) continue;  // shared generator instances, atmosphere objects: not settable
            rows[d.info.name] = Row{d.info, d.declarer, d.value, {}, {}, {}};
        }
        auto touchRow = [&](const KeyInfo& k) -> Row& {
            auto it = rows.find(k.name);
            if (it == rows.end()) it = rows.emplace(k.name, Row{k, "", "", {}, {}, {}}).first;
            return it->second;
        };
        for (auto& e : p.elements()) {
            for (auto& k : e->optionKeys()) touchRow(k).options.insert(e->name());
            for (auto& k : e->readKeys()) touchRow(k).readers.insert(e->name());
            for (auto& k : e->writeKeys()) touchRow(k).writers.insert(e->name());
        }
        for (Generator* g : p.generatorOrder()) {
            for (auto& k : g->inputs()) touchRow(k).readers.insert(g->name());
            for (auto& k : g->outputs()) touchRow(k).writers.insert(g->name());
        }
        for (auto it = rows.begin(); it != rows.end();)
            it = it->second.info.typeName == std::string("object") ? rows.erase(it) : std::next(it);
        p.release();
    }
    if (o.json) {
        nlohmann::json j = nlohmann::json::array();
        for (auto& [name, r] : rows) {
            nlohmann::json k = {{"name", name},
                                {"type", typeText(r.info)},
                                {"unit", r.info.unit},
                                {"default", r.value},
                                {"description", r.info.description},
                                {"declared_by", r.declarer},
                                {"option_of", r.options},
                                {"read_by", r.readers},
                                {"written_by", r.writers}};
            if (r.info.range) k["range"] = {r.info.range->min, r.info.range->max};
            else k["range"] = nullptr;
            if (!r.info.choices.empty()) k["choices"] = r.info.choices;
            j.push_back(k);
        }
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    if (o.markdown) {
        std::printf("| key | type | unit | range | default | description | option of | read by | written by |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|\n");
        for (auto& [name, r] : rows) {
            std::string v = r.value.size() > 40 ? r.value.substr(0, 37) + "..." : r.value;
            std::printf("| `%s` | %s | %s | %s | %s | %s | %s | %s | %s |\n", name.c_str(), typeText(r.info).c_str(), r.info.unit.c_str(),
                        r.info.choices.empty() ? rangeText(r.info.range).c_str() : join(r.info.choices).c_str(), v.c_str(), r.info.description.c_str(), join(r.options).c_str(),
                        join(r.readers).c_str(), join(r.writers).c_str());
        }
        return 0;
    }
    for (auto& [name, r] : rows) {
        std::printf("%s  %s%s%s%s%s\n", name.c_str(), typeText(r.info).c_str(), r.info.unit.empty() ? "" : (" " + r.info.unit).c_str(),
                    r.info.range ? (" " + rangeText(r.info.range)).c_str() : (r.info.choices.empty() ? "" : (" {" + join(r.info.choices) + "}").c_str()), r.value.empty() ? "" : (" = " + r.value).c_str(),
                    r.options.empty() ? "" : ("  (option of " + join(r.options) + ")").c_str());
        if (!r.info.description.empty()) std::printf("    %s\n", r.info.description.c_str());
        if (!r.readers.empty()) std::printf("    read by: %s\n", join(r.readers).c_str());
        if (!r.writers.empty()) std::printf("    written by: %s\n", join(r.writers).c_str());
    }
    return 0;
}

Registrar reg("vars", "list every SkyVars key: type, unit, range, default, and who reads or writes it", [](CLI::App& sub) {
    auto o = std::make_shared<VarsOptions>();  // the action below owns it
    sub.add_flag("--json", o->json, "machine-readable JSON array");
    sub.add_flag("--markdown", o->markdown, "a Markdown table (docs/keys.md)");
    sub.add_option("--elements", o->elements, "comma list of elements to include (default: every known element)");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
