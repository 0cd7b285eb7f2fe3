#include <fmt/format.h>

#include "commands.hpp"
#include "manta/aero/database.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/config.hpp"

namespace manta::cli {

void add_config(CLI::App& app, Action& action) {
    auto* cfg = app.add_subcommand("config", "Configuration files");
    cfg->require_subcommand(1);
    auto* check = cfg->add_subcommand(
        "check", "Validate an aircraft file or an aero database without running anything");
    auto file = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    check->add_option("FILE", *file, "Aircraft YAML or aero database file")->required();
    check->add_flag("--json", *json, "Print one JSON object");
    check->callback([=, &action] {
        action = [=]() -> int {
            const auto node = core::ConfigNode::parse_file(*file);
            std::string kind;
            std::string summary;
            if (node.has("manta_aero_database")) {
                const auto db = aero::AeroDatabase::read(*file);
                kind = "aero-database";
                summary = fmt::format("{} tables, force axes {}", db.tables().size(),
                                      aero::to_string(db.force_axes()));
            } else {
                const auto a = aircraft::load_aircraft(*file);
                kind = "aircraft";
                summary = fmt::format("'{}', {} mass cases, aero: {}", a.name, a.mass_cases.size(),
                                      a.aero_label);
            }
            if (*json) {
                print_json(
                    {{"file", *file}, {"kind", kind}, {"valid", true}, {"summary", summary}});
            } else {
                fmt::print("{}: valid {} ({})\n", *file, kind, summary);
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
