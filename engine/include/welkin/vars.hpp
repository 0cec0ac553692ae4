// SkyVars: the scene's shared, typed key/value registry.
//
//   inline const welkin::Key<double> kTurbidity{"sky.turbidity", {1.0, 10.0}, "Linke turbidity (1)"};
//   welkin::SkyVars vars = welkin::SkyVars::earth();
//   vars.declare(kTurbidity, 2.0);        // a second element declaring it shares the same value
//   vars.set(kTurbidity, 3.0);            // validated against [1, 10]; bumps the version
//   double t = vars.get(kTurbidity);      // unset or wrong-typed reads throw, naming the key
//   uint64_t v = vars.version(kTurbidity);
//   vars.setFromString("sky.turbidity", "4");   // what `--var sky.turbidity=4` does: parsed by type
//
//   // An enumerated key takes and prints names; C++ reads the value it names.
//   inline const welkin::EnumKey<int> kQuality{"demo.quality", {{"low", 0}, {"high", 1}}, "preset"};
//   vars.declare(kQuality, 1);                 // by value: stored as "high"
//   vars.setFromString("demo.quality", "low"); // names only: "ultra" or "2" is refused, listing the names
//   int q = kQuality.value(vars);              // 0
//
// Threads: a SkyVars is used from one thread at a time, reads included (a read updates its lookup
// cache); share values between threads by copying them out.
//
// Declarations: a key declared by two parties (elements, generators, the host) must agree on
// type, range and unit; a disagreement is an error naming both declarers (who is declaring is
// set by SkyVars::DeclarerScope, which SkyProcessor opens around each element and generator).
//
// Keys are typed (Key<T>); values are one of: bool, int, double, glm::dvec2/3/4, glm::dmat3/4,
// std::string, TextureRef (a non-owning GL texture handle) or std::shared_ptr<U> (a shared
// object such as a generator instance). Every value carries a version, bumped whenever set()
// changes it (setting an equal value leaves the version alone): generators compare versions to
// decide whether they must run again.
#pragma once
#include <welkin/error.hpp>

#include <glm/glm.hpp>

#include <any>
#include <cmath>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <typeindex>
#include <unordered_map>
#include <bit>
#include <cstring>
#include <utility>
#include <vector>

namespace welkin {

/// Non-owning reference to a GL texture owned by a generator or element (id 0 = none).
struct TextureRef {
    unsigned id = 0;      ///< GL texture name
    unsigned target = 0;  ///< GL_TEXTURE_2D, GL_TEXTURE_3D, ...
    int width = 0, height = 0, depth = 0;
    bool operator==(const TextureRef&) const = default;
};

/// The names a string key accepts (an enumeration): setting any other text is an error that lists
/// them. Empty: any text.
struct Choices {
    std::vector<std::string> names;
    bool operator==(const Choices&) const = default;
};

/// Closed numeric range for a key; both ends inclusive.
struct Range {
    double min = 0.0;
    double max = 0.0;
    bool operator==(const Range&) const = default;
};

namespace detail {
template <class T> struct TypeName { static constexpr const char* value = "object"; };
template <> struct TypeName<bool> { static constexpr const char* value = "bool"; };
template <> struct TypeName<int> { static constexpr const char* value = "int"; };
template <> struct TypeName<double> { static constexpr const char* value = "double"; };
template <> struct TypeName<glm::dvec2> { static constexpr const char* value = "dvec2"; };
template <> struct TypeName<glm::dvec3> { static constexpr const char* value = "dvec3"; };
template <> struct TypeName<glm::dvec4> { static constexpr const char* value = "dvec4"; };
template <> struct TypeName<glm::dmat3> { static constexpr const char* value = "dmat3"; };
template <> struct TypeName<glm::dmat4> { static constexpr const char* value = "dmat4"; };
template <> struct TypeName<std::string> { static constexpr const char* value = "string"; };
template <> struct TypeName<TextureRef> { static constexpr const char* value = "texture"; };

template <class T> struct IsSharedPtr : std::false_type {};
template <class U> struct IsSharedPtr<std::shared_ptr<U>> : std::true_type {};

template <class T>
constexpr bool kSupported = std::is_same_v<T, bool> || std::is_same_v<T, int> || std::is_same_v<T, double> ||
                            std::is_same_v<T, glm::dvec2> || std::is_same_v<T, glm::dvec3> ||
                            std::is_same_v<T, glm::dvec4> || std::is_same_v<T, glm::dmat3> ||
                            std::is_same_v<T, glm::dmat4> || std::is_same_v<T, std::string> ||
                            std::is_same_v<T, TextureRef> || IsSharedPtr<T>::value;
}  // namespace detail

/// Type-erased description of a key (for element declarations, stats and error messages).
struct KeyInfo {
    std::string name;
    std::type_index type = typeid(void);
    const char* typeName = "";
    std::optional<Range> range;
    std::string description;
    std::string unit;  ///< e.g. "m", "rad", "lx", "cd/m^2"; "" for dimensionless or non-numeric values
    std::vector<std::string> choices;  ///< an enumerated string key's names (empty: any text)
};

/// The unit implied by a key name's suffix ("observer.height_m" -> "m"), or "".
std::string unitFromKeyName(std::string_view name);

namespace detail {
/// A new key serial, unique in the process (never 0, never reused): SkyVars' lookup cache is keyed
/// on it, so a key object made later at a freed key's address is never mistaken for it.
uint64_t nextKeySerial();
}  // namespace detail

/// A typed key. Name them `area.quantity_unit` (e.g. "observer.height_m", "sun.direction").
template <class T>
class Key {
    static_assert(detail::kSupported<T>, "Key<T>: unsupported value type");

public:
    /// `unit` defaults to the one the name's suffix implies (unitFromKeyName).
    explicit Key(std::string name, std::string description = {}, std::string unit = {})
        : name_(std::move(name)), description_(std::move(description)), unit_(unitOr(unit, name_)) {}
    /// A key whose scalar values (or every component of a vector) must lie in `range`.
    Key(std::string name, Range range, std::string description = {}, std::string unit = {})
        : name_(std::move(name)), range_(range), description_(std::move(description)), unit_(unitOr(unit, name_)) {}
    /// An enumerated string key: its values are one of `choices` (see also EnumKey).
    Key(std::string name, Choices choices, std::string description = {})
        requires std::is_same_v<T, std::string>
        : name_(std::move(name)), description_(std::move(description)), choices_(std::move(choices.names)) {}

    const std::string& name() const { return name_; }
    const std::optional<Range>& range() const { return range_; }
    const std::string& description() const { return description_; }
    const std::string& unit() const { return unit_; }
    const std::vector<std::string>& choices() const { return choices_; }
    /// Unique in the process and shared by copies (same name, range and unit): what SkyVars'
    /// lookup cache is keyed on.
    uint64_t serial() const { return serial_; }
    KeyInfo info() const { return {name_, typeid(T), detail::TypeName<T>::value, range_, description_, unit_, choices_}; }

private:
    static std::string unitOr(const std::string& unit, const std::string& name) { return unit.empty() ? unitFromKeyName(name) : unit; }
    std::string name_;
    std::optional<Range> range_;
    std::string description_;
    std::string unit_;
    std::vector<std::string> choices_;
    uint64_t serial_ = detail::nextKeySerial();
};

template <class E>
class EnumKey;

/// One row of SkyVars::describe(): what `welkin vars` lists.
struct KeyDescription {
    KeyInfo info;
    std::string declarer;  ///< who declared it first ("host" when no DeclarerScope was open)
    std::string value;     ///< current value as text ("" if unset or not representable)
    bool isSet = false;
};

class SkyVars {
public:
    SkyVars() : identity_(newIdentity()) {}
    SkyVars(const SkyVars&) = delete;
    SkyVars& operator=(const SkyVars&) = delete;
    /// The entries move with their identity (versionSlot() pointers stay valid); the moved-from
    /// object is empty, with an identity of its own.
    SkyVars(SkyVars&& o) noexcept
        : entries_(std::move(o.entries_)), declarer_(std::move(o.declarer_)), identity_(o.identity_), cache_(o.cache_) {
        o.entries_.clear();
        o.identity_ = newIdentity();
        o.cache_.fill({});
    }
    SkyVars& operator=(SkyVars&& o) noexcept {
        if (this != &o) {
            entries_ = std::move(o.entries_);
            declarer_ = std::move(o.declarer_);
            identity_ = o.identity_;
            cache_ = o.cache_;
            o.entries_.clear();
            o.identity_ = newIdentity();
            o.cache_.fill({});
        }
        return *this;
    }

    /// Earth defaults: observer, time, camera, exposure and quality keys (and, as elements are
    /// added to the library, their shared keys such as the atmosphere).
    static SkyVars earth();

    /// Declares `key` with a default value. If the key already exists with the same type, the
    /// existing value is kept and shared; a different type is an error naming the key.
    template <class T>
    void declare(const Key<T>& key, T defaultValue) {
        if (Entry* e = find(key)) {
            checkCompatible(*e, key.info());
            if (!e->isSet) {
                validate(key.name(), e->range, defaultValue);
                checkChoice(key.name(), e->choices, defaultValue);
                e->value = std::move(defaultValue);
                e->isSet = true;
                ++e->version;
            }
            return;
        }
        validate(key.name(), key.range(), defaultValue);
        checkChoice(key.name(), key.choices(), defaultValue);
        entries_.emplace(key.name(), makeEntry(key.info(), std::any(std::move(defaultValue)), true));
    }
    /// Declares an enumerated key with the value named by `defaultValue`.
    template <class E>
    void declare(const EnumKey<E>& key, E defaultValue);

    /// Declares `key` with no value yet: reading it before set() is an error.
    template <class T>
    void declareUnset(const Key<T>& key) {
        if (Entry* e = find(key)) {
            checkCompatible(*e, key.info());
            return;
        }
        entries_.emplace(key.name(), makeEntry(key.info(), std::any(), false));
    }

    /// Names who is declaring keys until destroyed (an element, a generator, "host"); nests.
    class DeclarerScope {
    public:
        DeclarerScope(SkyVars& vars, std::string who) : vars_(vars), previous_(std::move(vars.declarer_)) { vars.declarer_ = std::move(who); }
        ~DeclarerScope() { vars_.declarer_ = std::move(previous_); }
        DeclarerScope(const DeclarerScope&) = delete;
        DeclarerScope& operator=(const DeclarerScope&) = delete;

    private:
        SkyVars& vars_;
        std::string previous_;
    };
    /// Who is declaring now ("host" outside any DeclarerScope).
    const std::string& declarer() const { return declarer_; }

    /// Sets a value (declaring the key if needed), validating the key's range. The version is
    /// bumped only if the value changed.
    template <class T>
    void set(const Key<T>& key, T value) {
        validate(key.name(), key.range(), value);
        checkChoice(key.name(), key.choices(), value);
        CacheLine* line = nullptr;
        Entry* found = find(key, &line);
        if (!found) {
            entries_.emplace(key.name(), makeEntry(key.info(), std::any(std::move(value)), true));
            return;
        }
        Entry& e = *found;
        checkType<T>(e, key.name());
        // The key's declaration against the entry's: once agreed, they keep agreeing (a Key is
        // immutable and an entry only adopts a range, unit or names it lacked), so the cache line
        // remembers it and later sets skip the comparison (and the KeyInfo it may build).
        if (!line || !line->agreed) {
            if (e.range != key.range() || e.unit != key.unit() || e.choices != key.choices()) checkCompatible(e, key.info());
            if (line) line->agreed = true;
        }
        if (e.range && !key.range()) validate(key.name(), e.range, value);
        if (key.choices().empty()) checkChoice(key.name(), e.choices, value);
        if (T* held = std::any_cast<T>(&e.value)) {
            if (e.isSet && *held == value) return;
            *held = std::move(value);  // in place: a dvec3 or a matrix is not reallocated per change
        } else {
            e.value = std::move(value);
        }
        e.isSet = true;
        ++e.version;
    }

    /// Sets an enumerated key to the name of `value` (an error if `value` has no name).
    template <class E>
    void set(const EnumKey<E>& key, E value);

    /// The value of `key`. Throws welkin::Error naming the key if unset or of another type.
    template <class T>
    const T& get(const Key<T>& key) const {
        const Entry* e = find(key);
        if (!e || !e->isSet) throw Error("SkyVars: key '" + key.name() + "' is not set");
        checkType<T>(*e, key.name());
        return *std::any_cast<T>(&e->value);
    }

    /// The value of `key`, or `fallback` if it is not set (wrong type is still an error).
    template <class T>
    T getOr(const Key<T>& key, T fallback) const {
        return has(key) ? get(key) : fallback;
    }

    /// Shared object under `key`, created with `make()` on first request: the way two elements
    /// share one generator instance (one transmittance LUT for Sky and Clouds).
    template <class U>
    std::shared_ptr<U> obtain(const Key<std::shared_ptr<U>>& key, const std::function<std::shared_ptr<U>()>& make) {
        if (has(key)) return get(key);
        auto obj = make();
        set(key, obj);
        return obj;
    }

    template <class T>
    bool has(const Key<T>& key) const {
        const Entry* e = find(key);
        return e && e->isSet;
    }
    bool contains(std::string_view name) const { return entries_.find(name) != entries_.end(); }

    /// Sets a value and always bumps its version (a generator republishing a texture it rewrote
    /// in place: the TextureRef is equal, the contents are new).
    template <class T>
    void publish(const Key<T>& key, T value) {
        const uint64_t before = version(key);
        set(key, std::move(value));
        if (Entry* e = find(key); e && e->version == before) ++e->version;
    }

    /// Bumps the version of a declared key without changing its value: a generator that rewrote a
    /// texture in place (same TextureRef) tells its readers. Throws if `name` is undeclared.
    void touch(std::string_view name);
    template <class T>
    void touch(const Key<T>& key) { touch(key.name()); }

    /// Sets a declared key from text, parsed by the key's type: bool (true/false/on/off/1/0),
    /// int, double, dvec2..4 ("x,y,z"), string. A key whose unit is "rad" also accepts degrees
    /// with a "deg" suffix ("15deg"). Range-checked; throws one line naming the key and the
    /// accepted range. Objects, textures and matrices cannot be set from text.
    void setFromString(std::string_view name, std::string_view text);
    /// The value of a key as text (the same syntax setFromString() accepts), "" if unset or not
    /// representable (objects, textures).
    std::string valueString(std::string_view name) const;
    /// Scalar components of a numeric key's value (bool, int, double, dvecN, dmatN; column-major),
    /// or an empty vector if unset or not numeric. For change tolerances.
    std::vector<double> numeric(std::string_view name) const;
    /// Every declared key, sorted by name.
    std::vector<KeyDescription> describe() const;
    /// Type, range, unit of a declared key (nullopt if undeclared).
    std::optional<KeyInfo> info(std::string_view name) const;

    /// Version counter of a key (0 if unset or undeclared); bumped on every change.
    uint64_t version(std::string_view name) const {
        auto it = entries_.find(name);  // heterogeneous: no string built
        return it == entries_.end() ? 0 : it->second.version;
    }
    template <class T>
    uint64_t version(const Key<T>& key) const {
        const Entry* e = find(key);
        return e ? e->version : 0;
    }
    /// Where the version counter of a declared key lives (nullptr if undeclared): the pointer stays
    /// valid, and the counter current, for this object's lifetime (keys are never removed) and
    /// through a move. For readers that poll many versions every frame without a lookup each (the
    /// generator graph); remember identity() with it.
    const uint64_t* versionSlot(std::string_view name) const {
        auto it = entries_.find(name);
        return it == entries_.end() ? nullptr : &it->second.version;
    }
    /// This object's identity, unique in the process (never reused, not even at the same address):
    /// a cache of versionSlot() pointers checks it before use.
    uint64_t identity() const { return identity_; }

    /// Names of all declared keys, sorted.
    std::vector<std::string> names() const;
    /// Type name ("double", "dvec3", ...) of a declared key, or "" if undeclared.
    std::string typeName(std::string_view name) const;

private:
    struct Entry {
        std::any value;
        std::type_index type;
        const char* typeName;
        std::optional<Range> range;
        uint64_t version = 0;
        bool isSet = false;
        std::string unit, description, declarer;
        std::vector<std::string> choices;
    };

    Entry makeEntry(const KeyInfo& k, std::any value, bool isSet) const {
        Entry e{std::move(value), k.type, k.typeName, k.range, isSet ? 1u : 0u, isSet, k.unit, k.description, declarer_, k.choices};
        return e;
    }
    /// Throws if `k` disagrees with the entry's type, range or unit, naming both declarers; adopts
    /// the range, unit and description when the entry had none.
    void checkCompatible(Entry& e, const KeyInfo& k) const;

    template <class T>
    static void checkType(const Entry& e, const std::string& name) {
        if (e.type != std::type_index(typeid(T)))
            throw Error("SkyVars: key '" + name + "' holds " + e.typeName + ", requested " + detail::TypeName<T>::value);
    }

    template <class T>
    static void validate(const std::string& name, const std::optional<Range>& range, const T& value) {
        if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int>) {
            checkScalar(name, range, double(value));
        } else if constexpr (std::is_same_v<T, glm::dvec2> || std::is_same_v<T, glm::dvec3> || std::is_same_v<T, glm::dvec4>) {
            for (int i = 0; i < T::length(); ++i) checkScalar(name, range, value[i]);
        } else if constexpr (std::is_same_v<T, glm::dmat3> || std::is_same_v<T, glm::dmat4>) {
            for (int c = 0; c < T::length(); ++c)
                for (int r = 0; r < T::length(); ++r) checkScalar(name, range, value[c][r]);
        }
    }
    // Inline: every set() of a number checks each component (dmat4: 16); only failures go out of line.
    static void checkScalar(const std::string& name, const std::optional<Range>& range, double v) {
        if (std::isfinite(v) && (!range || (v >= range->min && v <= range->max))) [[likely]]
            return;
        failScalar(name, range, v);
    }
    [[noreturn]] static void failScalar(const std::string& name, const std::optional<Range>& range, double v);
    template <class T>
    static void checkChoice(const std::string& name, const std::vector<std::string>& choices, const T& value) {
        if constexpr (std::is_same_v<T, std::string>) checkName(name, choices, value);
    }
    /// Throws "key 'NAME': 'VALUE' is not one of a, b, c" unless `choices` is empty or holds it.
    static void checkName(const std::string& name, const std::vector<std::string>& choices, const std::string& value);

    /// Hashes a key's name; transparent, so a lookup by string_view builds no string. Inline, eight
    /// bytes a step (a multiply-rotate mix per word; the names are short ASCII and differ anywhere):
    /// about a third of the instructions of the library's std::hash call for a 20-character name.
    struct NameHash {
        using is_transparent = void;
        std::size_t operator()(std::string_view s) const noexcept {
            uint64_t h = 0x9E3779B97F4A7C15ull ^ s.size();
            size_t i = 0;
            for (; i + 8 <= s.size(); i += 8) {
                uint64_t w;
                std::memcpy(&w, s.data() + i, 8);
                h = std::rotl((h ^ w) * 0xBF58476D1CE4E5B9ull, 29);
            }
            uint64_t w = 0;
            for (size_t k = 0; i + k < s.size(); ++k) w |= uint64_t(static_cast<unsigned char>(s[i + k])) << (8 * k);
            h = (h ^ w) * 0x94D049BB133111EBull;
            return size_t(h ^ (h >> 31));
        }
    };
    // Hashed rather than ordered: every frame reads and versions a few hundred keys, and an ordered
    // map's string comparisons were the largest share of the framework's own instructions per frame
    // (docs/hardening.md). Listings (names(), describe()) sort.
    std::unordered_map<std::string, Entry, NameHash, std::equal_to<>> entries_;
    std::string declarer_ = "host";
    uint64_t identity_;
    static uint64_t newIdentity();

    // Lookup cache: a key object's serial -> its entry, direct-mapped. The elements and generators
    // read and set a few hundred keys by Key object every frame; a hit costs a mask and a compare
    // where the hashed lookup hashed and compared the name (docs/hardening.md). Only entries that
    // exist are cached, and entries are never removed (unordered_map nodes keep their address
    // through rehashes and moves of the map), so a cached pointer stays valid for this object's
    // life. Serials are never reused, so a stale line cannot match another key. Consequence: even
    // const reads write the cache, so a SkyVars must not be used from two threads at once.
    struct CacheLine {
        uint64_t serial = 0;    ///< 0: empty
        Entry* entry = nullptr;
        bool agreed = false;    ///< set() found this key's declaration compatible with the entry
    };
    static constexpr size_t kCacheLines = 512;
    mutable std::array<CacheLine, kCacheLines> cache_{};

    template <class T>
    Entry* find(const Key<T>& key, CacheLine** lineOut = nullptr) const {
        CacheLine& line = cache_[key.serial() & (kCacheLines - 1)];
        if (lineOut) *lineOut = &line;
        if (line.serial == key.serial()) return line.entry;
        auto it = entries_.find(key.name());
        if (it == entries_.end()) {
            if (lineOut) *lineOut = nullptr;
            return nullptr;
        }
        Entry* e = const_cast<Entry*>(&it->second);
        line = {key.serial(), e, false};
        return e;
    }
};

/// An enumerated key: stored and shown as a name (what `--var`, JSON and `welkin vars` use), read
/// in C++ as the value the name stands for. `E` is any equality-comparable type (an enum class or
/// an int level).
template <class E>
class EnumKey : public Key<std::string> {
public:
    EnumKey(std::string name, std::vector<std::pair<std::string, E>> values, std::string description = {})
        : Key<std::string>(std::move(name), Choices{namesOf(values)}, std::move(description)), values_(std::move(values)) {}

    /// The value a name stands for; throws naming the key and the accepted names.
    E valueOf(const std::string& text) const {
        for (const auto& [n, v] : values_)
            if (n == text) return v;
        throw Error("key '" + name() + "': '" + text + "' is not one of " + list());
    }
    /// The name of a value; throws if the value has none.
    const std::string& nameOf(E value) const {
        for (const auto& [n, v] : values_)
            if (v == value) return n;
        throw Error("key '" + name() + "': no name for the value given (names: " + list() + ")");
    }
    /// The value of the key in `vars` (throws if unset).
    E value(const SkyVars& vars) const { return valueOf(vars.get(static_cast<const Key<std::string>&>(*this))); }
    /// The value of the key in `vars`, or `fallback` if unset.
    E valueOr(const SkyVars& vars, E fallback) const {
        return vars.has(static_cast<const Key<std::string>&>(*this)) ? value(vars) : fallback;
    }
    const std::vector<std::pair<std::string, E>>& values() const { return values_; }

private:
    static std::vector<std::string> namesOf(const std::vector<std::pair<std::string, E>>& values) {
        std::vector<std::string> out;
        for (const auto& [n, v] : values) out.push_back(n);
        return out;
    }
    std::string list() const {
        std::string out;
        for (const auto& [n, v] : values_) out += (out.empty() ? "" : ", ") + n;
        return out;
    }
    std::vector<std::pair<std::string, E>> values_;
};

template <class E>
void SkyVars::declare(const EnumKey<E>& key, E defaultValue) {
    declare(static_cast<const Key<std::string>&>(key), key.nameOf(defaultValue));
}
template <class E>
void SkyVars::set(const EnumKey<E>& key, E value) {
    set(static_cast<const Key<std::string>&>(key), key.nameOf(value));
}

}  // namespace welkin
