#pragma once
/// @file avl_mass.hpp
/// Reader of AVL's mass file (`.mass`, AVL 3.40): the units, gravity and air density lines and the
/// table of mass items, summed into the total mass, the centre of gravity and the inertia tensor
/// about it. In MANTA the centre of gravity is the moment reference point of `manta vlm --mass`
/// (docs/avl-input.md, "Mass file"); the other values are read, checked and reported.
///
/// The file, as AVL reads it:
/// * `Lunit = 0.3048 m`, `Munit = 0.4535 kg`, `Tunit = 1.0 s`: the size of the file's length,
///   mass and time units and their names (each 1 and "Lunit", "Munit", "Tunit" if absent). The
///   length unit is the .avl file's.
/// * `g = 9.81`, `rho = 1.225`: gravity and air density in the units named above.
/// * data lines `mass x y z [Ixx Iyy Izz [Ixy Ixz Iyz]]` (missing columns 0), each item's
///   inertias about its own centre of gravity;
/// * a line starting with `*` sets multipliers and one starting with `+` adders of the columns
///   (as many as it gives), applied as value * multiplier + adder to every data line after it.
/// `#` starts a comment line, `!` a remark to the end of the line.
///
/// Every malformed line is an InputError of one line, "file:line: problem; expected ...": an
/// unknown `name = value`, a data line with a word that is not a number, NaN, infinity or an
/// implausible magnitude in any field, a total mass that is not positive. (AVL prints "Bad data
/// line ignored" and goes on; MANTA stops, so that a typing error does not move the CG.)

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace manta::vlm {

/// The contents of an AVL mass file.
struct AvlMass {
    /// Size of the file's length unit (Lunit, the .avl file's unit too) in the unit named
    /// `length_unit_name`: `Lunit = 0.3048 m` gives 0.3048 and "m".
    double length_unit = 1.0;
    std::string length_unit_name = "Lunit";
    double mass_unit = 1.0;  ///< `Munit = 0.4535 kg`: 0.4535 and "kg"
    std::string mass_unit_name = "Munit";
    double time_unit = 1.0;  ///< `Tunit = 1.0 s`
    std::string time_unit_name = "Tunit";
    std::optional<double> gravity;  ///< `g`, in the units named by the file
    std::optional<double> density;  ///< `rho`, in the units named by the file
    int items = 0;                  ///< data lines
    double mass = 0.0;              ///< total mass [Munit], > 0
    /// Centre of gravity in the geometry axes and length unit of the .avl file (Lunit).
    Eigen::Vector3d cg = Eigen::Vector3d::Zero();
    /// Inertia tensor about the centre of gravity [Munit Lunit^2]: Ixx Iyy Izz on the diagonal,
    /// the products as -sum(m x y) etc. off it (AVL's "Ixx -Ixy -Ixz" matrix; the run file's Ixy,
    /// Iyz, Izx are these off-diagonal elements).
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    std::string source;  ///< the file name, for messages

    /// The values in the units the file names (m, kg for AVL's samples).
    [[nodiscard]] double dimensional_mass() const { return mass * mass_unit; }
    [[nodiscard]] Eigen::Vector3d dimensional_cg() const { return cg * length_unit; }
    [[nodiscard]] Eigen::Matrix3d dimensional_inertia() const {
        return inertia * (mass_unit * length_unit * length_unit);
    }
};

/// Read an AVL mass file. IoError if it cannot be read, InputError for malformed content.
[[nodiscard]] AvlMass read_avl_mass(const std::filesystem::path& file);

/// Parse the text of an AVL mass file; `source` names it in messages.
[[nodiscard]] AvlMass parse_avl_mass(std::string_view text, const std::string& source);

}  // namespace manta::vlm
