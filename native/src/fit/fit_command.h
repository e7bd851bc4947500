// `purl fit`: loads the targets, fits, prints progress on stderr and writes the preset.
#pragma once
#include <string>
#include <vector>

namespace purl {

struct FitCommand {
    std::vector<std::string> scenes;   // one per target, or one shared by every target
    std::vector<std::string> targets;  // images
    std::vector<std::string> masks;    // none, or one per target
    std::string params;                // comma-separated; "" = default_fit_parameter_list()
    std::string output;                // preset JSON
    std::string name;                  // preset name ("" = the output's file stem)
    int iterations = 20, spp = 0, threads = 0;
    long long seed = -1;
    double tolerance = 1e-3;
    int block = 1;
    std::string error = "linear";  // FitError by name
};

// Returns the process exit status; throws InputError for bad input.
int run_fit_command(const FitCommand& command);

}  // namespace purl
