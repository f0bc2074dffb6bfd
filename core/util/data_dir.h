// Where glintlab finds the files it reads at run time, and where it writes when not told.
//
// The data folder holds shaders/, experiments/ (the built-in experiments, camera paths, the report's
// and tune's Python scripts) and metrics/color/ocio/config.ocio, laid out as in the source tree.
// It is, in this order:
//   - $GLINTLAB_DATA_DIR when set and not empty;
//   - the source tree, for a program inside the build folder it was built in;
//   - <the executable's folder>/../share/glintlab otherwise: where `cmake --install` and the Debian
//     package put it (bin/glintlab beside share/glintlab/); for the Python module, share/glintlab of
//     the prefix it is installed in (set_data_anchor).
// The default output folder (`--out`, `--cache`, `--study`) is $GLINTLAB_RESULTS_DIR when set and not
// empty, the source tree's results/ for a program in the build folder, else results/ in the current
// folder. The executable's path is /proc/self/exe. glintlab's own libraries (core/util/plugin.h) are
// in the build folder for a program inside it, else in PREFIX/lib/glintlab.
#pragma once

#include <string>

namespace glintlab {

struct DataLocations {
  std::string data;     // the data folder
  std::string why;      // why that folder: "$GLINTLAB_DATA_DIR", "the source tree of the build folder ..." or
                        // "../share/glintlab beside the executable ..."
  std::string results;  // the default output folder
  std::string plugins;  // where glintlab's own libraries are (core/util/plugin.h): the build folder for a
                        // program in it, else PREFIX/lib/glintlab; "" where unknown
};

// The locations for a program at `executable` with the two variables set to `data_env` and
// `results_env` ("" for unset); `executable` lies `depth` folders below the installation prefix
// (bin/glintlab: 1), whose share/glintlab is the data folder.
DataLocations locate_data(const std::string& data_env, const std::string& results_env, const std::string& executable,
                          int depth = 1);

// For code loaded into another program (the Python module): the file it was loaded from and its
// depth below the prefix (lib/python3/dist-packages/glintlab/_core.so: 4) take the place of
// /proc/self/exe. Call before the first data_locations().
void set_data_anchor(const std::string& file, int depth);

// "" when `where.data` holds the files glintlab reads, else an error that names the folder, why it
// was chosen, the missing file and GLINTLAB_DATA_DIR.
std::string data_dir_problem(const DataLocations& where);

// The locations of this process, found on first use.
const DataLocations& data_locations();

// data_locations().data + "/" + relative, e.g. data_path("shaders"). Throws IoError with
// data_dir_problem()'s message when the data folder is incomplete.
std::string data_path(const std::string& relative);

// data_locations().results + "/" + relative, or the folder itself for "".
std::string results_path(const std::string& relative = "");

}  // namespace glintlab
