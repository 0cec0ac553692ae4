// welkin vars: every SkyVars key of a scene with all known elements: type, unit, range, default,
// description, who declares it, and the elements and generators that read or write it.
// --keys-of engine|NAME[,...]: the keys tables of the docs, one per owner, each from a scene of
// its own so that no table depends on which other element folders exist: `engine` is a scene
// with no element (docs/keys.md); an element NAME's table is the keys a scene of that element
// alone has beyond the engine's (skyelements/NAME/keys.md).
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
    std::string keysOf;  // "engine", an element's name, or a comma list of them
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

using Rows = std::map<std::string, Row>;

// Every key of a scene with the elements `names` (none: the engine's own), with who reads and
// writes it. Needs a current GL context.
Rows collect(const std::vector<std::string>& names, Logger& log) {
    Rows rows;
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
    return rows;
}

void printMarkdown(const Rows& rows) {
    std::printf("| key | type | unit | range | default | description | option of | read by | written by |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (auto& [name, r] : rows) {
        std::string v = r.value.size() > 40 ? r.value.substr(0, 37) + "..." : r.value;
        std::printf("| `%s` | %s | %s | %s | %s | %s | %s | %s | %s |\n", name.c_str(), typeText(r.info).c_str(), r.info.unit.c_str(),
                    r.info.choices.empty() ? rangeText(r.info.range).c_str() : join(r.info.choices).c_str(), v.c_str(), r.info.description.c_str(), join(r.options).c_str(),
                    join(r.readers).c_str(), join(r.writers).c_str());
    }
}

// --keys-of: one table per owner; before each table of a list, a line naming its file.
// The owners --keys-of names, checked (before any GL context is made).
std::vector<std::string> keysOfOwners(const VarsOptions& o) {
    if (!o.json && !o.markdown) throw Error("--keys-of: give --markdown or --json");
    if (!o.elements.empty()) throw Error("--keys-of: --elements does not apply (each table has its own scene)");
    std::vector<std::string> owners;
    for (const std::string& n : elements::parseElementList(o.keysOf)) {
        if (n != "engine" && !elements::findDescriptor(n)) {
            throw Error("--keys-of: '" + n + "' is neither 'engine' nor a known element (known: " + join(elements::knownElements()) + ")");
        }
        owners.push_back(n);
    }
    return owners;
}

int runKeysOf(const VarsOptions& o, const std::vector<std::string>& owners, Logger& log) {
    const Rows engine = collect({}, log);
    nlohmann::json all = nlohmann::json::object();
    for (size_t i = 0; i < owners.size(); ++i) {
        Rows rows;
        if (owners[i] == "engine") {
            rows = engine;
        } else {
            for (auto& [name, r] : collect({owners[i]}, log))
                if (!engine.count(name)) rows.emplace(name, r);
        }
        const std::string file = owners[i] == "engine" ? "docs/keys.md" : "skyelements/" + owners[i] + "/keys.md";
        if (o.json) {
            nlohmann::json keys = nlohmann::json::array();
            for (auto& [name, r] : rows) keys.push_back(name);
            all[owners[i]] = {{"file", file}, {"keys", keys}};
            continue;
        }
        if (owners.size() > 1) std::printf("%s<!-- keys of %s: %s -->\n", i ? "\n" : "", owners[i].c_str(), file.c_str());
        printMarkdown(rows);
    }
    if (o.json) std::printf("%s\n", all.dump(2).c_str());
    return 0;
}

int run(const VarsOptions& o) {
    Logger log;
    const std::vector<std::string> owners = o.keysOf.empty() ? std::vector<std::string>{} : keysOfOwners(o);
    auto ctx = gl::HeadlessContext::create({}, log);
    if (!o.keysOf.empty()) return runKeysOf(o, owners, log);
    std::vector<std::string> names = o.elements.empty() ? elements::knownElements() : elements::expandElementList(o.elements);
    const Rows rows = collect(names, log);
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
        printMarkdown(rows);
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
    sub.add_option("--keys-of", o->keysOf,
                   "the docs' keys tables (with --markdown or --json): 'engine' = the keys of a scene with no element "
                   "(docs/keys.md); an element's name = the keys a scene of it alone adds (skyelements/NAME/keys.md); "
                   "a comma list prints each table after a line naming its file");
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
