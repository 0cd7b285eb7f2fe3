#include "manta/core/config.hpp"

#include <yaml-cpp/yaml.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "manta/core/error.hpp"
#include "manta/core/utf8.hpp"

namespace manta::core {

struct ConfigNode::Impl {
    YAML::Node node;
    std::string source;
    std::string path;
    int line = 0;  // 1-based
};

namespace {

int mark_line(const YAML::Node& n) {
    if (!n.IsDefined()) return 0;
    const auto m = n.Mark();
    return m.line >= 0 ? m.line + 1 : 0;
}

std::string join_path(const std::string& parent, std::string_view key) {
    if (parent.empty()) return std::string(key);
    return fmt::format("{}.{}", parent, key);
}

std::string fmt_num(double v) {
    return fmt::format("{:g}", v);
}

// A scalar that looks like "15.5 m" or "10deg": a number followed by a unit word.
bool looks_like_number_with_unit(const std::string& s) {
    std::size_t i = 0;
    while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.' ||
                            s[i] == '-' || s[i] == '+' || s[i] == 'e' || s[i] == 'E'))
        ++i;
    if (i == 0 || i == s.size()) return false;
    while (i < s.size() && s[i] == ' ') ++i;
    return i < s.size() && std::isalpha(static_cast<unsigned char>(s[i]));
}

// One pass over a parsed document, before any reader sees it:
//  - a repeated mapping key is refused (yaml-cpp keeps both entries and look-ups see only the
//    first, so a repeated key would silently lose a value);
//  - a key that is a mapping or a list is refused (readers look keys up by their text);
//  - every key and text value must be UTF-8 (JSON output is UTF-8; RFC 8259, section 8.1);
//  - aliases are walked once: yaml-cpp gives an alias the very node of its anchor, so a node met
//    again is skipped, and the pass costs time in proportion to the nodes written, not to the
//    nodes the aliases expand to ("billion laughs": ten levels of ten aliases name 10^10 nodes
//    from 100 written). A document whose aliases expand it beyond `max_expanded_nodes` (and ten
//    times its written size) is refused, since a reader that walks it would see every copy.
constexpr std::uint64_t max_expanded_nodes = 1'000'000;

class DocumentCheck {
public:
    DocumentCheck(std::string_view text, const std::string& source)
        : text_(text), source_(source) {}

    void run(const YAML::Node& root) {
        const std::uint64_t expanded = walk(root, "");
        if (expanded > max_expanded_nodes && expanded > 10 * distinct_) {
            throw ConfigError(fmt::format(
                "{}: aliases ('*name') expand the document to {} nodes from {} written; expected "
                "at most {} nodes after alias expansion (nested aliases of aliases, a "
                "'billion laughs' document?)",
                source_,
                expanded >= saturated ? std::string("more than 10^18")
                                      : fmt::format("{}", expanded),
                distinct_, max_expanded_nodes));
        }
        // Bytes outside every value (comments) must be UTF-8 too: YAML streams are Unicode
        // (YAML 1.2, section 5.2).
        const std::size_t bad = utf8_invalid_offset(text_);
        if (bad != std::string_view::npos) {
            throw ConfigError(
                fmt::format("{}:{}: text is not valid UTF-8 ({} of the file); "
                            "expected UTF-8 text (save the file as UTF-8)",
                            source_, line_of_offset(text_, bad), describe_utf8_error(text_, bad)));
        }
    }

private:
    static constexpr std::uint64_t saturated = 1'000'000'000'000'000'000ULL;

    void check_text(const YAML::Node& n, const std::string& path, const char* what) const {
        const std::string& s = n.Scalar();
        const std::size_t bad = utf8_invalid_offset(s);
        if (bad == std::string::npos) return;
        // The file offset of the bad byte, when it is in the file as written (a quoted escape
        // such as "\uD800" makes invalid UTF-8 from valid text).
        std::string file_offset;
        const std::size_t raw = utf8_invalid_offset(text_);
        const int line = mark_line(n);
        if (raw != std::string_view::npos && static_cast<int>(line_of_offset(text_, raw)) == line)
            file_offset = fmt::format(", byte offset {} of the file", raw);
        throw ConfigError(fmt::format(
            "{}:{}: key '{}': {} '{}' is not valid UTF-8 (byte 0x{:02X} at byte offset {} of "
            "the {}{}); expected UTF-8 text (save the file as UTF-8)",
            source_, line, utf8_escaped(path), what, utf8_escaped(s),
            static_cast<unsigned>(static_cast<unsigned char>(s[bad])), bad, what, file_offset));
    }

    // Expanded size of `n` (saturating), checking each distinct node once.
    std::uint64_t walk(const YAML::Node& n, const std::string& path) {
        if (n.IsScalar()) {
            check_text(n, path, "value");
            return 1;
        }
        if (!n.IsMap() && !n.IsSequence()) return 1;
        auto& bucket = seen_[n.Mark().pos];
        for (const auto& [node, size] : bucket)
            if (node.is(n)) return size;
        ++distinct_;
        std::uint64_t size = 1;
        const auto add = [&size](std::uint64_t k) { size = std::min(saturated, size + k); };
        if (n.IsMap()) {
            std::unordered_map<std::string, int> keys;
            for (const auto& kv : n) {
                const int line = mark_line(kv.first);
                if (kv.first.IsMap() || kv.first.IsSequence()) {
                    throw ConfigError(fmt::format(
                        "{}:{}: key '{}' has a {} as a key; expected text keys ('key: value')",
                        source_, line, path.empty() ? "<top level>" : utf8_escaped(path),
                        kv.first.IsMap() ? "mapping" : "list"));
                }
                const std::string key = kv.first.Scalar();
                if (kv.first.IsScalar()) check_text(kv.first, join_path(path, key), "key");
                const auto [it, fresh] = keys.emplace(key, line);
                if (!fresh) {
                    throw ConfigError(
                        fmt::format("{}:{}: key '{}' appears twice in one mapping (first at line "
                                    "{}); expected each key once",
                                    source_, line, join_path(path, key), it->second));
                }
                add(1);
                add(walk(kv.second, join_path(path, key)));
            }
        } else {
            for (std::size_t i = 0; i < n.size(); ++i)
                add(walk(n[i], fmt::format("{}[{}]", path, i)));
        }
        seen_[n.Mark().pos].emplace_back(n, size);
        return size;
    }

    std::string_view text_;
    const std::string& source_;
    std::unordered_map<int, std::vector<std::pair<YAML::Node, std::uint64_t>>> seen_;
    std::uint64_t distinct_ = 0;
};

// Unit suffixes users put on keys; MANTA reads SI (and _deg for angles) only.
constexpr std::array<std::string_view, 14> foreign_unit_suffixes = {
    "_ft",   "_in",  "_kt", "_kts", "_lb",  "_lbf",     "_lbs",
    "_slug", "_mph", "_km", "_kmh", "_rad", "_percent", "_nm"};

}  // namespace

// ---------------------------------------------------------------- NumberSpec

std::string NumberSpec::describe() const {
    std::string s = "a number";
    if (min && max) {
        s += fmt::format(" in {}{}, {}{}", min_exclusive ? "(" : "[", fmt_num(*min), fmt_num(*max),
                         max_exclusive ? ")" : "]");
    } else if (min) {
        s += fmt::format(" {} {}", min_exclusive ? ">" : ">=", fmt_num(*min));
    } else if (max) {
        s += fmt::format(" {} {}", max_exclusive ? "<" : "<=", fmt_num(*max));
    }
    if (!unit.empty()) s += fmt::format(" [{}]", unit);
    return s;
}

bool NumberSpec::accepts(double v) const {
    if (!std::isfinite(v)) return false;
    if (min && (min_exclusive ? !(v > *min) : !(v >= *min))) return false;
    if (max && (max_exclusive ? !(v < *max) : !(v <= *max))) return false;
    return true;
}

// ---------------------------------------------------------------- ConfigNode

ConfigNode::ConfigNode() : impl_(std::make_shared<Impl>()) {}
ConfigNode::ConfigNode(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

ConfigNode ConfigNode::parse_file(const std::filesystem::path& file) {
    // An ifstream opens a directory on Linux and reads nothing: say what is wrong instead.
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec))
        throw IoError(fmt::format("{}: is a directory; expected a YAML file", file.string()));
    std::ifstream in(file);
    if (!in) throw IoError(fmt::format("{}: cannot open file for reading", file.string()));
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_string(ss.str(), file.string());
}

ConfigNode ConfigNode::parse_string(std::string_view text, std::string source) {
    auto impl = std::make_shared<Impl>();
    impl->source = std::move(source);
    try {
        impl->node = YAML::Load(std::string(text));
    } catch (const YAML::Exception& e) {
        throw ConfigError(
            fmt::format("{}:{}: YAML syntax error: {}", impl->source, e.mark.line + 1, e.msg));
    }
    DocumentCheck(text, impl->source).run(impl->node);
    impl->line = impl->node.IsDefined() && !impl->node.IsNull() ? mark_line(impl->node) : 1;
    return ConfigNode(std::move(impl));
}

const std::string& ConfigNode::source() const {
    return impl_->source;
}
const std::string& ConfigNode::key_path() const {
    return impl_->path;
}
int ConfigNode::line() const {
    return impl_->line;
}

std::string ConfigNode::where() const {
    std::string s = impl_->source.empty() ? "<config>" : impl_->source;
    if (impl_->line > 0) s += fmt::format(":{}", impl_->line);
    if (!impl_->path.empty()) s += fmt::format(": key '{}'", impl_->path);
    return s;
}

std::string ConfigNode::value_text() const {
    const auto& n = impl_->node;
    if (!n.IsDefined()) return "<missing>";
    if (n.IsNull()) return "<empty>";
    if (n.IsMap()) return "<mapping>";
    if (n.IsSequence()) return "<sequence>";
    return n.Scalar();
}

bool ConfigNode::is_defined() const {
    return impl_->node.IsDefined();
}
bool ConfigNode::is_null() const {
    return impl_->node.IsDefined() && impl_->node.IsNull();
}
bool ConfigNode::is_map() const {
    return impl_->node.IsMap();
}
bool ConfigNode::is_sequence() const {
    return impl_->node.IsSequence();
}
bool ConfigNode::is_scalar() const {
    return impl_->node.IsScalar();
}
std::size_t ConfigNode::size() const {
    return impl_->node.size();
}

ConfigNode ConfigNode::element(std::size_t i) const {
    auto c = std::make_shared<Impl>();
    c->source = impl_->source;
    c->path = fmt::format("{}[{}]", impl_->path, i);
    c->node = impl_->node[i];
    c->line = c->node.IsDefined() ? mark_line(c->node) : impl_->line;
    return ConfigNode(std::move(c));
}

bool ConfigNode::has(std::string_view key) const {
    if (!impl_->node.IsMap()) return false;
    for (const auto& kv : impl_->node)
        if (kv.first.Scalar() == key) return true;
    return false;
}

ConfigNode ConfigNode::child(std::string_view key) const {
    auto c = std::make_shared<Impl>();
    c->source = impl_->source;
    c->path = join_path(impl_->path, key);
    c->line = impl_->line;
    if (impl_->node.IsMap()) {
        for (const auto& kv : impl_->node) {
            if (kv.first.Scalar() == key) {
                c->node = kv.second;
                c->line = mark_line(kv.first);
                break;
            }
        }
    }
    return ConfigNode(std::move(c));
}

std::vector<std::string> ConfigNode::map_keys() const {
    std::vector<std::string> keys;
    if (impl_->node.IsMap())
        for (const auto& kv : impl_->node) keys.push_back(kv.first.Scalar());
    return keys;
}

int ConfigNode::key_line(std::string_view key) const {
    if (impl_->node.IsMap())
        for (const auto& kv : impl_->node)
            if (kv.first.Scalar() == key) return mark_line(kv.first);
    return 0;
}

void ConfigNode::fail(std::string_view problem, std::string_view expected) const {
    throw ConfigError(
        fmt::format("{}: value '{}' {}; expected {}", where(), value_text(), problem, expected));
}

double ConfigNode::to_double(const NumberSpec& spec) const {
    const auto& n = impl_->node;
    if (!n.IsDefined() || n.IsNull()) fail("is missing", spec.describe());
    if (!n.IsScalar()) fail("is not a number", spec.describe());
    const std::string& s = n.Scalar();
    double v = 0.0;
    std::size_t used = 0;
    try {
        v = std::stod(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != s.size()) {
        if (looks_like_number_with_unit(s))
            fail("carries a unit in the value",
                 fmt::format("{} written as a plain number (units are not read from values)",
                             spec.describe()));
        fail("is not a number", spec.describe());
    }
    if (!std::isfinite(v)) fail("is not finite", spec.describe());
    if (!spec.accepts(v)) fail("is out of range", spec.describe());
    return v;
}

long ConfigNode::to_integer(const NumberSpec& spec) const {
    const double v = to_double(spec);
    if (std::floor(v) != v) fail("is not an integer", "an integer " + spec.describe().substr(2));
    // Beyond 2^53 a double no longer holds every integer, and a cast past LONG_MAX is undefined.
    if (std::abs(v) > 9007199254740992.0)
        fail("is too large", "an integer " + spec.describe().substr(2));
    return static_cast<long>(v);
}

bool ConfigNode::to_bool() const {
    const auto& n = impl_->node;
    if (!n.IsScalar()) fail("is not a boolean", "true or false");
    const std::string& s = n.Scalar();
    if (s == "true" || s == "True" || s == "yes") return true;
    if (s == "false" || s == "False" || s == "no") return false;
    fail("is not a boolean", "true or false");
}

std::string ConfigNode::to_string() const {
    const auto& n = impl_->node;
    if (!n.IsDefined() || n.IsNull()) fail("is missing", "a text value");
    if (!n.IsScalar()) fail("is not a text value", "a text value");
    return n.Scalar();
}

std::vector<double> ConfigNode::to_doubles(std::size_t n, const NumberSpec& spec) const {
    const auto expected = n ? fmt::format("a list of {} numbers, each {}", n, spec.describe())
                            : fmt::format("a list of numbers, each {}", spec.describe());
    if (!impl_->node.IsSequence()) fail("is not a list", expected);
    if (n != 0 && impl_->node.size() != n)
        fail(fmt::format("has {} entries", impl_->node.size()), expected);
    if (impl_->node.size() == 0) fail("is empty", expected);
    std::vector<double> out;
    out.reserve(impl_->node.size());
    for (std::size_t i = 0; i < impl_->node.size(); ++i) out.push_back(element(i).to_double(spec));
    return out;
}

// ---------------------------------------------------------------- ConfigMap

ConfigMap::ConfigMap(ConfigNode node) : node_(std::move(node)) {
    if (!node_.is_map()) node_.fail("is not a mapping", "a mapping of 'key: value' lines");
}

void ConfigMap::remember(std::string_view key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
}

bool ConfigMap::has(std::string_view key) {
    remember(key);
    return node_.has(key);
}

namespace {
// " (found 'aera' at line 12: a misspelling?)" when the map holds a key that was never asked
// for and is close to the missing `key`; else empty.
std::string misspelling_hint(const ConfigNode& map, const std::vector<std::string>& known,
                             std::string_view key) {
    std::vector<std::string> unknown;
    for (const auto& k : map.map_keys())
        if (std::find(known.begin(), known.end(), k) == known.end()) unknown.push_back(k);
    // The key with a unit suffix ("ceiling_ft" for "ceiling"): MANTA reads SI.
    for (const auto& k : unknown) {
        if (k.size() > key.size() + 1 && k.starts_with(key) && k[key.size()] == '_') {
            return fmt::format(
                " (found '{}' at line {}: MANTA reads '{}' in SI units{})", k, map.key_line(k), key,
                std::find(known.begin(), known.end(), std::string(key) + "_deg") != known.end()
                    ? fmt::format(" or '{}_deg' in degrees", key)
                    : "");
        }
    }
    const std::string guess = closest_match(key, unknown);
    if (guess.empty()) return {};
    return fmt::format(" (found '{}' at line {}: a misspelling?)", guess, map.key_line(guess));
}
}  // namespace

ConfigNode ConfigMap::required(std::string_view key) {
    remember(key);
    if (!node_.has(key)) {
        throw ConfigError(fmt::format("{}: missing required key '{}'{}", node_.where(),
                                      join_path(node_.key_path(), key),
                                      misspelling_hint(node_, known_, key)));
    }
    return node_.child(key);
}

void ConfigMap::fail(std::string_view key, std::string_view problem, std::string_view expected) {
    node_.child(key).fail(problem, expected);
}

double ConfigMap::number(std::string_view key, const NumberSpec& spec) {
    return required(key).to_double(spec);
}

double ConfigMap::number_or(std::string_view key, double fallback, const NumberSpec& spec) {
    return has(key) ? node_.child(key).to_double(spec) : fallback;
}

long ConfigMap::integer(std::string_view key, const NumberSpec& spec) {
    return required(key).to_integer(spec);
}

long ConfigMap::integer_or(std::string_view key, long fallback, const NumberSpec& spec) {
    return has(key) ? node_.child(key).to_integer(spec) : fallback;
}

std::vector<double> ConfigMap::numbers(std::string_view key, std::size_t n,
                                       const NumberSpec& spec) {
    return required(key).to_doubles(n, spec);
}

std::array<double, 3> ConfigMap::vec3(std::string_view key, const NumberSpec& spec) {
    const auto v = required(key).to_doubles(3, spec);
    return {v[0], v[1], v[2]};
}

bool ConfigMap::has_angle(std::string_view key) {
    const std::string deg_key = std::string(key) + "_deg";
    const bool a = has(key);
    const bool b = has(deg_key);
    return a || b;
}

namespace {
NumberSpec to_degrees(const NumberSpec& s) {
    NumberSpec d = s;
    if (d.min) *d.min *= 180.0 / std::numbers::pi;
    if (d.max) *d.max *= 180.0 / std::numbers::pi;
    d.unit = "deg";
    return d;
}
NumberSpec widened(const NumberSpec& s, std::string unit) {
    NumberSpec w = s;
    w.min.reset();
    w.max.reset();
    w.unit = std::move(unit);
    return w;
}
}  // namespace

double ConfigMap::angle(std::string_view key, const NumberSpec& spec) {
    const std::string deg_key = std::string(key) + "_deg";
    remember(key);
    remember(deg_key);
    const bool rad = node_.has(key);
    const bool deg = node_.has(deg_key);
    if (rad && deg) {
        node_.child(deg_key).fail(
            fmt::format("duplicates '{}'", key),
            fmt::format("either '{}' (radians) or '{}' (degrees), not both", key, deg_key));
    }
    if (!rad && !deg) {
        throw ConfigError(fmt::format("{}: missing required key '{}' (or '{}' in degrees){}",
                                      node_.where(), join_path(node_.key_path(), key), deg_key,
                                      misspelling_hint(node_, known_, deg_key)));
    }
    if (deg) {
        const ConfigNode n = node_.child(deg_key);
        const double v = n.to_double(widened(spec, "deg"));
        const NumberSpec d = to_degrees(spec);
        if (!d.accepts(v)) n.fail("is out of range", d.describe());
        return v * std::numbers::pi / 180.0;
    }
    const ConfigNode n = node_.child(key);
    const double v = n.to_double(widened(spec, "rad"));
    if (std::abs(v) > 2.0 * std::numbers::pi) {
        n.fail("is in radians but looks like degrees",
               fmt::format(
                   "{} (write it as '{}' to give degrees)",
                   NumberSpec{spec.min, spec.max, spec.min_exclusive, spec.max_exclusive, "rad"}
                       .describe(),
                   deg_key));
    }
    NumberSpec r = spec;
    r.unit = "rad";
    if (!r.accepts(v)) n.fail("is out of range", r.describe());
    return v;
}

double ConfigMap::angle_or(std::string_view key, double fallback_rad, const NumberSpec& spec) {
    return has_angle(key) ? angle(key, spec) : fallback_rad;
}

std::array<double, 2> ConfigMap::angle_range(std::string_view key, const NumberSpec& spec) {
    const std::string deg_key = std::string(key) + "_deg";
    remember(key);
    remember(deg_key);
    const bool deg = node_.has(deg_key);
    if (deg && node_.has(key)) {
        node_.child(deg_key).fail(
            fmt::format("duplicates '{}'", key),
            fmt::format("either '{}' (radians) or '{}' (degrees), not both", key, deg_key));
    }
    if (!deg && !node_.has(key)) {
        throw ConfigError(fmt::format("{}: missing required key '{}' (or '{}' in degrees){}",
                                      node_.where(), join_path(node_.key_path(), key), deg_key,
                                      misspelling_hint(node_, known_, deg_key)));
    }
    const ConfigNode n = node_.child(deg ? deg_key : std::string(key));
    const NumberSpec s =
        deg ? to_degrees(spec)
            : NumberSpec{spec.min, spec.max, spec.min_exclusive, spec.max_exclusive, "rad"};
    // Read without bounds first, so a radian value that looks like degrees is reported as such
    // rather than as merely out of range.
    auto v = n.to_doubles(2, widened(s, s.unit));
    if (!deg && (std::abs(v[0]) > 2 * std::numbers::pi || std::abs(v[1]) > 2 * std::numbers::pi))
        n.fail("is in radians but looks like degrees",
               fmt::format("{} (write it as '{}' to give degrees)", s.describe(), deg_key));
    for (std::size_t i = 0; i < 2; ++i)
        if (!s.accepts(v[i])) n.element(i).fail("is out of range", s.describe());
    if (v[0] > v[1])
        n.fail("has its lower bound above its upper bound", "[lower, upper] with lower <= upper");
    const double f = deg ? std::numbers::pi / 180.0 : 1.0;
    return {v[0] * f, v[1] * f};
}

std::string ConfigMap::string(std::string_view key) {
    return required(key).to_string();
}

std::string ConfigMap::string_or(std::string_view key, std::string fallback) {
    return has(key) ? node_.child(key).to_string() : fallback;
}

std::string ConfigMap::choice(std::string_view key,
                              std::initializer_list<std::string_view> choices) {
    const ConfigNode n = required(key);
    const std::string v = n.to_string();
    std::vector<std::string> list(choices.begin(), choices.end());
    if (std::find(list.begin(), list.end(), v) == list.end()) {
        std::string expected = fmt::format("one of {}", fmt::join(list, ", "));
        const std::string guess = closest_match(v, list);
        if (!guess.empty()) expected += fmt::format(" (did you mean '{}'?)", guess);
        n.fail("is not a valid choice", expected);
    }
    return v;
}

std::string ConfigMap::choice_or(std::string_view key, std::string fallback,
                                 std::initializer_list<std::string_view> choices) {
    if (!has(key)) return fallback;
    return choice(key, choices);
}

bool ConfigMap::boolean_or(std::string_view key, bool fallback) {
    return has(key) ? node_.child(key).to_bool() : fallback;
}

ConfigNode ConfigMap::child(std::string_view key) {
    return required(key);
}

std::optional<ConfigNode> ConfigMap::optional_child(std::string_view key) {
    if (!has(key)) return std::nullopt;
    return node_.child(key);
}

ConfigMap ConfigMap::map(std::string_view key) {
    return ConfigMap(required(key));
}

ConfigNode ConfigMap::sequence(std::string_view key, bool allow_empty) {
    ConfigNode n = required(key);
    if (!n.is_sequence()) n.fail("is not a list", "a list ('- item' lines or [a, b])");
    if (!allow_empty && n.size() == 0) n.fail("is empty", "at least one entry");
    return n;
}

void ConfigMap::finish() const {
    for (const std::string& key : node_.map_keys()) {
        if (std::find(known_.begin(), known_.end(), key) != known_.end()) continue;
        const ConfigNode n = node_.child(key);
        std::string hint;
        for (const auto suffix : foreign_unit_suffixes) {
            if (key.size() > suffix.size() && key.ends_with(suffix)) {
                const std::string base = key.substr(0, key.size() - suffix.size());
                if (std::find(known_.begin(), known_.end(), base) != known_.end()) {
                    hint = fmt::format(
                        " (MANTA reads '{}' in SI units{}; convert the value)", base,
                        std::find(known_.begin(), known_.end(), base + "_deg") != known_.end()
                            ? fmt::format(", or '{}_deg' in degrees", base)
                            : "");
                    break;
                }
            }
        }
        if (hint.empty()) {
            const std::string guess = closest_match(key, known_);
            if (!guess.empty()) hint = fmt::format(" (did you mean '{}'?)", guess);
        }
        std::vector<std::string> valid = known_;
        std::sort(valid.begin(), valid.end());
        throw ConfigError(fmt::format("{}: unknown key '{}'{}; valid keys here: {}", n.where(), key,
                                      hint, fmt::join(valid, ", ")));
    }
}

// ---------------------------------------------------------------- suggestions

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t sub =
                prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t best_d = std::string::npos;
    for (const auto& c : candidates) {
        const std::size_t d = edit_distance(word, c);
        if (d < best_d) {
            best_d = d;
            best = c;
        }
    }
    const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
    return best_d <= limit ? best : std::string();
}

}  // namespace manta::core
