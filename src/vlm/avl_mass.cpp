#include "manta/vlm/avl_mass.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/vlm/detail/avl_text.hpp"

namespace manta::vlm {

namespace {

using detail::avl::Line;
using detail::avl::Word;

constexpr std::string_view row_fields = "mass x y z [Ixx Iyy Izz [Ixy Ixz Iyz]]";
constexpr std::array<const char*, 10> column_names = {"mass", "x",   "y",   "z",   "Ixx",
                                                      "Iyy",  "Izz", "Ixy", "Ixz", "Iyz"};
/// Plausible magnitudes of one item after its multipliers and adders: mass [Munit], position
/// [Lunit], inertias [Munit Lunit^2].
constexpr std::array<double, 10> column_limit = {1e12, 1e6,  1e6,  1e6,  1e18,
                                                 1e18, 1e18, 1e18, 1e18, 1e18};
constexpr double max_multiplier = 1e12;  ///< `*` and `+` values
constexpr double min_unit = 1e-9, max_unit = 1e9;

class MassReader {
public:
    MassReader(std::string_view text, const std::string& source)
        : lines_(detail::avl::significant_lines(text)), source_(source) {}

    AvlMass read() {
        AvlMass m;
        m.source = source_;
        std::array<double, 10> fac{}, add{};
        fac.fill(1.0);
        add.fill(0.0);
        double sm = 0.0;
        Eigen::Vector3d smx = Eigen::Vector3d::Zero();
        Eigen::Matrix3d smxx = Eigen::Matrix3d::Zero();  // sum m x_i x_j
        Eigen::Matrix3d own = Eigen::Matrix3d::Zero();   // items' own inertia tensors
        for (const Line& l : lines_) {
            const char c0 = l.text.front();
            if (c0 == '*' || c0 == '+') {
                set_columns(l, c0 == '*' ? fac : add, c0 == '*' ? "multiplier" : "adder");
                continue;
            }
            if (const auto eq = l.text.find('='); eq != std::string::npos) {
                parameter(l, eq, m);
                continue;
            }
            const auto v = row(l);
            std::array<double, 10> r{};
            for (std::size_t k = 0; k < 10; ++k) {
                r[k] = fac[k] * v[k] + add[k];
                if (!(std::abs(r[k]) <= column_limit[k]))
                    fail(l, fmt::format("{} = {:g} (after the multiplier {:g} and adder {:g}); "
                                        "expected a magnitude up to {:g}",
                                        column_names[k], r[k], fac[k], add[k], column_limit[k]));
            }
            const double mi = r[0];
            const Eigen::Vector3d x(r[1], r[2], r[3]);
            sm += mi;
            smx += mi * x;
            const Eigen::Matrix3d xx = x * x.transpose();  // x_i x_j: symmetric to the bit
            smxx += mi * xx;
            Eigen::Matrix3d j;
            j << r[4], -r[7], -r[8], -r[7], r[5], -r[9], -r[8], -r[9], r[6];
            own += j;
            ++m.items;
        }
        const int end = lines_.empty() ? 1 : lines_.back().number;
        if (m.items == 0)
            throw InputError(fmt::format("{}:{}: no mass items; expected data lines '{}'", source_,
                                         end, row_fields));
        if (!(sm > 0.0))
            throw InputError(fmt::format(
                "{}:{}: the total mass of the {} items is {:g}; expected a positive total", source_,
                end, m.items, sm));
        m.mass = sm;
        m.cg = smx / sm;
        // Parallel axes: J = sum J_i + sum m (|x|^2 I - x x^T), moved to the centre of gravity.
        const Eigen::Matrix3d cgcg = m.cg * m.cg.transpose();
        const Eigen::Matrix3d second = smxx - sm * cgcg;
        const Eigen::Matrix3d j = own + second.trace() * Eigen::Matrix3d::Identity() - second;
        m.inertia = 0.5 * (j + j.transpose());  // exactly symmetric
        return m;
    }

private:
    std::vector<Line> lines_;
    const std::string& source_;

    [[noreturn]] void fail(const Line& l, std::string_view message) const {
        throw InputError(fmt::format("{}:{}: {}", source_, l.number, message));
    }

    /// The numbers of `words` from `first`, all of them; an error for any other word.
    std::vector<double> all_numbers(const Line& l, const std::vector<std::string>& ws,
                                    std::size_t first, std::string_view expected) const {
        std::vector<double> v;
        for (std::size_t i = first; i < ws.size(); ++i) {
            double x = 0.0;
            switch (detail::avl::read_word(ws[i], x)) {
                case Word::number:
                    v.push_back(x);
                    break;
                case Word::non_finite:
                    fail(l, detail::avl::non_finite_message(ws[i], expected));
                case Word::text:
                    fail(l, fmt::format("'{}' is not a number; expected {}", ws[i], expected));
            }
        }
        return v;
    }

    void set_columns(const Line& l, std::array<double, 10>& columns, std::string_view what) {
        const auto ws = detail::avl::words(std::string_view(l.text).substr(1));
        const std::string expected =
            fmt::format("up to 10 {}s of the columns {}", what, row_fields);
        const auto v = all_numbers(l, ws, 0, expected);
        if (v.empty() || v.size() > 10)
            fail(l, fmt::format("{} {}s in '{}'; expected {}", v.size(), what, l.text, expected));
        for (std::size_t k = 0; k < v.size(); ++k) {
            if (!(std::abs(v[k]) <= max_multiplier))
                fail(l, fmt::format("{} of {} = {:g}; expected a magnitude up to {:g}", what,
                                    column_names[k], v[k], max_multiplier));
            columns[k] = v[k];
        }
    }

    std::array<double, 10> row(const Line& l) const {
        const auto v = all_numbers(l, detail::avl::words(l.text), 0, row_fields);
        if (v.size() < 4 || v.size() > 10)
            fail(l, fmt::format("{} numbers in '{}'; expected {}, or 'name = value', or a "
                                "multiplier line '* ...' or adder line '+ ...'",
                                v.size(), l.text, row_fields));
        std::array<double, 10> r{};
        for (std::size_t k = 0; k < v.size(); ++k) r[k] = v[k];
        return r;
    }

    void parameter(const Line& l, std::size_t eq, AvlMass& m) const {
        const std::string key = detail::avl::trim(std::string_view(l.text).substr(0, eq));
        const auto ws = detail::avl::words(std::string_view(l.text).substr(eq + 1));
        constexpr std::string_view keys = "Lunit, Munit, Tunit, g or rho";
        if (key != "Lunit" && key != "Munit" && key != "Tunit" && key != "g" && key != "rho")
            fail(l, fmt::format("unknown parameter '{}'; expected {} (then '= value')", key, keys));
        if (ws.empty()) fail(l, fmt::format("{}: no value after '='; expected a number", key));
        double v = 0.0;
        const Word w = detail::avl::read_word(ws[0], v);
        if (w == Word::non_finite)
            fail(l, fmt::format("{}: {}", key,
                                detail::avl::non_finite_message(ws[0], "a positive number")));
        if (w == Word::text)
            fail(l,
                 fmt::format("{}: '{}' is not a number; expected a positive number", key, ws[0]));
        if (!(v >= min_unit && v <= max_unit))
            fail(l, fmt::format("{} = {:g}; expected a positive number in [{:g}, {:g}]", key, v,
                                min_unit, max_unit));
        std::string name;
        for (std::size_t i = 1; i < ws.size(); ++i) name += (name.empty() ? "" : " ") + ws[i];
        if (key == "Lunit") {
            m.length_unit = v;
            if (!name.empty()) m.length_unit_name = name;
        } else if (key == "Munit") {
            m.mass_unit = v;
            if (!name.empty()) m.mass_unit_name = name;
        } else if (key == "Tunit") {
            m.time_unit = v;
            if (!name.empty()) m.time_unit_name = name;
        } else if (key == "g") {
            m.gravity = v;
        } else {
            m.density = v;
        }
    }
};

}  // namespace

AvlMass parse_avl_mass(std::string_view text, const std::string& source) {
    return MassReader(text, source).read();
}

AvlMass read_avl_mass(const std::filesystem::path& file) {
    const std::string text = core::read_file(file);
    return parse_avl_mass(text, file.string());
}

}  // namespace manta::vlm
