#pragma once
/// @file config.hpp
/// MANTA's one validation layer for YAML configuration. Every module reads its section through
/// `ConfigMap`, which records the keys a reader asks for; `finish()` rejects every other key with
/// the closest valid key suggested. Every error is one line naming file, line, key path, value and
/// what was expected. No yaml-cpp type appears outside this layer.

#include <array>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace manta::core {

/// Expectations on a number read from a configuration file.
struct NumberSpec {
    std::optional<double> min;  ///< lower bound (inclusive unless min_exclusive)
    std::optional<double> max;  ///< upper bound (inclusive unless max_exclusive)
    bool min_exclusive = false;
    bool max_exclusive = false;
    std::string unit;  ///< unit the value is read in, for messages ("m", "kg m^2", "-")

    [[nodiscard]] static NumberSpec positive(std::string unit) {
        return {0.0, std::nullopt, true, false, std::move(unit)};
    }
    [[nodiscard]] static NumberSpec non_negative(std::string unit) {
        return {0.0, std::nullopt, false, false, std::move(unit)};
    }
    [[nodiscard]] static NumberSpec range(double lo, double hi, std::string unit) {
        return {lo, hi, false, false, std::move(unit)};
    }
    [[nodiscard]] static NumberSpec any(std::string unit) {
        return {std::nullopt, std::nullopt, false, false, std::move(unit)};
    }
    /// "a number > 0 [m]" etc.
    [[nodiscard]] std::string describe() const;
    [[nodiscard]] bool accepts(double v) const;
};

/// A located node of a parsed YAML document (value semantics, cheap to copy).
class ConfigNode {
public:
    /// Parse a file; IoError if it cannot be read, ConfigError (with line) on YAML syntax errors.
    [[nodiscard]] static ConfigNode parse_file(const std::filesystem::path& file);
    /// Parse text; `source` names it in messages.
    [[nodiscard]] static ConfigNode parse_string(std::string_view text, std::string source);

    [[nodiscard]] const std::string& source() const;    ///< file name or source label
    [[nodiscard]] const std::string& key_path() const;  ///< e.g. "mass.cases[0].ixx"
    [[nodiscard]] int line() const;                     ///< 1-based line, 0 if unknown
    /// "file:line: key 'path'" prefix for messages.
    [[nodiscard]] std::string where() const;
    /// The node's text as written (scalars), or "<map>"/"<sequence>"/"<null>".
    [[nodiscard]] std::string value_text() const;

    [[nodiscard]] bool is_defined() const;
    [[nodiscard]] bool is_null() const;
    [[nodiscard]] bool is_map() const;
    [[nodiscard]] bool is_sequence() const;
    [[nodiscard]] bool is_scalar() const;
    [[nodiscard]] std::size_t size() const;

    [[nodiscard]] ConfigNode element(std::size_t i) const;       ///< sequence element
    [[nodiscard]] bool has(std::string_view key) const;          ///< map has key
    [[nodiscard]] ConfigNode child(std::string_view key) const;  ///< may be undefined
    [[nodiscard]] std::vector<std::string> map_keys() const;
    [[nodiscard]] int key_line(std::string_view key) const;  ///< line of a map key, 0 if unknown

    /// Scalar conversions; each throws ConfigError naming location, value and expectation.
    [[nodiscard]] double to_double(const NumberSpec& spec = {}) const;
    [[nodiscard]] long to_integer(const NumberSpec& spec = {}) const;
    [[nodiscard]] bool to_bool() const;
    [[nodiscard]] std::string to_string() const;
    /// Sequence of numbers; `n` = required length (0: any non-empty length).
    [[nodiscard]] std::vector<double> to_doubles(std::size_t n = 0,
                                                 const NumberSpec& spec = {}) const;

    /// Throw a ConfigError "<where>: value '<v>' <problem>; expected <expected>".
    [[noreturn]] void fail(std::string_view problem, std::string_view expected) const;

    struct Impl;
    explicit ConfigNode(std::shared_ptr<const Impl> impl);
    ConfigNode();

private:
    std::shared_ptr<const Impl> impl_;
};

/// Reader of one YAML mapping that records the keys asked for and rejects unknown ones.
class ConfigMap {
public:
    /// `node` must be a mapping (else ConfigError).
    explicit ConfigMap(ConfigNode node);

    [[nodiscard]] const ConfigNode& node() const { return node_; }
    /// Record `key` as valid and say whether it is present.
    [[nodiscard]] bool has(std::string_view key);

    [[nodiscard]] double number(std::string_view key, const NumberSpec& spec);
    [[nodiscard]] double number_or(std::string_view key, double fallback, const NumberSpec& spec);
    [[nodiscard]] long integer(std::string_view key, const NumberSpec& spec);
    [[nodiscard]] long integer_or(std::string_view key, long fallback, const NumberSpec& spec);
    [[nodiscard]] std::vector<double> numbers(std::string_view key, std::size_t n,
                                              const NumberSpec& spec);
    [[nodiscard]] std::array<double, 3> vec3(std::string_view key, const NumberSpec& spec);

    /// An angle, returned in radians, written either as `key` (radians) or `key_deg` (degrees).
    /// `spec` bounds are in radians. A radian value above 2*pi in magnitude is reported as a likely
    /// unit mistake.
    [[nodiscard]] double angle(std::string_view key, const NumberSpec& spec);
    [[nodiscard]] double angle_or(std::string_view key, double fallback_rad,
                                  const NumberSpec& spec);
    [[nodiscard]] bool has_angle(std::string_view key);
    /// Pair [lo, hi] of angles (radians) from `key` or `key_deg`, lo <= hi.
    [[nodiscard]] std::array<double, 2> angle_range(std::string_view key, const NumberSpec& spec);

    [[nodiscard]] std::string string(std::string_view key);
    [[nodiscard]] std::string string_or(std::string_view key, std::string fallback);
    /// A string that must be one of `choices`; the error lists them.
    [[nodiscard]] std::string choice(std::string_view key,
                                     std::initializer_list<std::string_view> choices);
    [[nodiscard]] std::string choice_or(std::string_view key, std::string fallback,
                                        std::initializer_list<std::string_view> choices);
    [[nodiscard]] bool boolean_or(std::string_view key, bool fallback);

    /// Required child node of any kind.
    [[nodiscard]] ConfigNode child(std::string_view key);
    [[nodiscard]] std::optional<ConfigNode> optional_child(std::string_view key);
    /// Required child mapping.
    [[nodiscard]] ConfigMap map(std::string_view key);
    /// Required sequence (non-empty unless allow_empty).
    [[nodiscard]] ConfigNode sequence(std::string_view key, bool allow_empty = false);

    /// Throw a ConfigError about `key` of this map.
    [[noreturn]] void fail(std::string_view key, std::string_view problem,
                           std::string_view expected);

    /// Reject keys never asked for, suggesting the closest known key. Call after reading.
    void finish() const;

private:
    [[nodiscard]] ConfigNode required(std::string_view key);
    void remember(std::string_view key);
    ConfigNode node_;
    std::vector<std::string> known_;
};

/// Levenshtein edit distance (used for "did you mean" suggestions).
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);
/// Closest candidate to `word` if reasonably close, else empty.
[[nodiscard]] std::string closest_match(std::string_view word,
                                        const std::vector<std::string>& candidates);

}  // namespace manta::core
