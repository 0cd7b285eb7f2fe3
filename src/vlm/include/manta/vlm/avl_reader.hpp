#pragma once
/// @file avl_reader.hpp
/// Reader of AVL geometry files (`.avl`, the input of Drela & Youngren's Athena Vortex Lattice
/// 3.40), so that a model prepared for AVL runs unchanged in MANTA's vortex-lattice module.
///
/// The supported subset, the mapping of every keyword onto `Model` and the keywords that are read
/// but ignored (each with a warning) are described in docs/avl-input.md. In short: the header
/// (title, Mach, symmetry, reference values, optional CDp), SURFACE blocks with COMPONENT/INDEX,
/// YDUPLICATE, SCALE, TRANSLATE, ANGLE, NOWAKE and sections with NACA, AIRFOIL, AFILE, CLAF and
/// CONTROL, and BODY blocks with YDUPLICATE, SCALE, TRANSLATE and BFILE. Lengths keep the file's
/// unit; angles (degrees in the file) are converted to radians.
///
/// Every malformed input is an InputError of one line, "file:line: KEYWORD: problem; expected
/// ...", e.g. `b737.avl:42: SECTION: expected 5 numbers (Xle Yle Zle Chord Ainc), got 'abc'`.
/// A file the model refers to (AFILE, BFILE) that cannot be read is an IoError naming that file
/// and the .avl line that refers to it.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "manta/vlm/model.hpp"

namespace manta::vlm {

/// Read the AVL geometry file `file`; airfoil (AFILE) and body (BFILE) files are looked up
/// relative to its folder. IoError if `file` or a file it names cannot be read, InputError for
/// malformed content. Warnings (keywords read but not modelled) are written to stderr, one line
/// each, prefixed "warning: ".
[[nodiscard]] Model read_avl(const std::filesystem::path& file);

/// As `read_avl(file)`, but the warnings are appended to `warnings` instead of being printed.
[[nodiscard]] Model read_avl(const std::filesystem::path& file, std::vector<std::string>& warnings);

/// Parse the text of an AVL geometry file. `source` names it in messages (normally the file
/// name); AFILE and BFILE names are relative to `base_dir`. Errors and warnings as `read_avl`.
[[nodiscard]] Model parse_avl(std::string_view text, const std::string& source,
                              const std::filesystem::path& base_dir);

/// As `parse_avl(text, source, base_dir)`, but the warnings are appended to `warnings`, each one
/// line naming source and line, instead of being printed.
[[nodiscard]] Model parse_avl(std::string_view text, const std::string& source,
                              const std::filesystem::path& base_dir,
                              std::vector<std::string>& warnings);

}  // namespace manta::vlm
