// glintlab._core: the C++ library bound with pybind11. The Python API (experiments/python/glintlab/
// __init__.py) normalises its arguments and calls these; each function here calls the same library
// function as the command line does (compare_images, measure_sequences, run_experiment,
// check_summary), with the GIL released while it works.
//
// Exceptions: ConfigError and std::invalid_argument (bad input, what the CLI exits 2 for) ->
// ValueError; IoError and std::filesystem::filesystem_error (exit 4) -> OSError; VulkanError and
// ShaderCompileError (exit 3) -> RuntimeError. The message is the CLI's.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <dlfcn.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/util/data_dir.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "core/vk/shader_compiler.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/check.h"
#include "experiments/cli/compare.h"
#include "experiments/runner/measure.h"
#include "experiments/sources/sequence.h"
#include "experiments/runner/runner.h"
#include "experiments/runner/version.h"
#include "metrics/color/image_io.h"

namespace py = pybind11;
using namespace glintlab;

namespace {

using FloatArray = py::array_t<float, py::array::c_style>;

// An Image handed to numpy without a copy: the array owns it through a capsule.
py::array to_array(Image&& img, std::vector<py::ssize_t> shape) {
  auto* owned = new Image(std::move(img));
  py::capsule free_it(owned, [](void* p) { delete static_cast<Image*>(p); });
  return py::array_t<float>(shape, owned->data.data(), free_it);
}

// The address of each array's pixels the last call of compare handed to compare_images, in the
// order reference, tests: what the tests check the arrays against (read in place, not copied).
std::vector<std::uintptr_t> last_compare_pixels;

// One input of compare: (path) or (array, name, tag, channels), the array H x W x C float32,
// C-contiguous, C in 1..4 (glintlab/__init__.py makes it so). Its pixels are read in place
// (CompareImage): `keep` holds the array until the comparison is done.
CompareImage compare_image(const py::tuple& t, std::vector<FloatArray>& keep) {
  CompareImage in;
  in.path = t[0].cast<std::string>();
  if (!t[1].is_none()) {
    keep.push_back(t[1].cast<FloatArray>());  // the same array where it is float32 and C-contiguous
    const FloatArray& a = keep.back();
    if (a.ndim() != 3) throw std::invalid_argument("compare: '" + in.path + "': an array of H x W x C allowed");
    in.pixels = a.data();
    in.height = int(a.shape(0));
    in.width = int(a.shape(1));
    in.channels = int(a.shape(2));
    in.tag = t[2].cast<std::string>();
  }
  return in;
}

py::tuple compare(const py::tuple& reference, const py::list& tests, const CompareOptions& options) {
  std::vector<FloatArray> keep;
  const CompareImage ref = compare_image(reference, keep);
  std::vector<CompareImage> test_images;
  for (const auto& t : tests) test_images.push_back(compare_image(t.cast<py::tuple>(), keep));
  last_compare_pixels.clear();
  last_compare_pixels.push_back(std::uintptr_t(ref.pixels));
  for (const CompareImage& in : test_images) last_compare_pixels.push_back(std::uintptr_t(in.pixels));
  std::ostringstream err;
  Comparison c;
  {
    py::gil_scoped_release unlocked;
    c = compare_images(options, ref, test_images, err);
  }
  py::list maps;
  for (std::size_t i = 0; i < c.tests.size(); ++i) {
    py::list per_metric;
    for (std::size_t m = 0; m < c.tests[i].metrics.size(); ++m) {
      Image map = comparison_map(c, i, m);
      if (map.empty()) {
        per_metric.append(py::none());
      } else {
        const py::ssize_t h = map.height, w = map.width;
        per_metric.append(to_array(std::move(map), {h, w}));
      }
    }
    maps.append(per_metric);
  }
  return py::make_tuple(dump_json(comparison_json(c)), maps, err.str(), comparison_exit_code(c));
}

py::array read_image(const std::string& path, const std::string& layer) {
  Image img;
  {
    py::gil_scoped_release unlocked;
    const FrameHeader h = read_frame_header(path);
    img = read_frame_channels(path, colour_channels(h, layer, path));
  }
  const py::ssize_t hh = img.height, w = img.width, c = img.channels;
  return to_array(std::move(img), {hh, w, c});
}

py::tuple read_sequence(const std::string& text, const std::string& layer) {
  Image all;
  std::vector<int> numbers;
  {
    py::gil_scoped_release unlocked;
    SequenceSpec seq = parse_sequence(text, "read_sequence");
    if (!layer.empty()) seq.layer = layer;
    std::vector<std::string> paths;
    for (const SequenceFrame& f : list_frames(seq, "read_sequence")) {
      numbers.push_back(f.number);
      paths.push_back(f.path);
    }
    const FrameHeader first = read_frame_header(paths[0]);
    const std::vector<std::string> channels = colour_channels(first, seq.layer, paths[0]);
    const std::size_t frame_values = std::size_t(first.width) * std::size_t(first.height) * 3;
    if (std::int64_t(frame_values) * std::int64_t(paths.size()) > 3 * kMaxSequencePixels * 4)
      throw ConfigError("read_sequence: '" + text + "' has " + std::to_string(paths.size()) + " frames of " +
                        std::to_string(first.width) + "x" + std::to_string(first.height) +
                        ": more than 4 x " + std::to_string(kMaxSequencePixels) + " pixels in all");
    all = Image::unfilled(first.width, first.height * int(paths.size()), 3);
    for (std::size_t k = 0; k < paths.size(); ++k) {
      const FrameHeader h = read_frame_header(paths[k]);
      if (h.width != first.width || h.height != first.height)
        throw ConfigError("read_sequence: '" + paths[k] + "' is " + std::to_string(h.width) + "x" +
                          std::to_string(h.height) + " but '" + paths[0] + "' is " + std::to_string(first.width) +
                          "x" + std::to_string(first.height) + " (every frame of a sequence must have one size)");
      const Image frame = read_frame_channels(paths[k], channels);
      std::copy(frame.data.begin(), frame.data.end(), all.data.begin() + std::ptrdiff_t(k * frame_values));
    }
  }
  const py::ssize_t t = py::ssize_t(numbers.size()), h = all.height / py::ssize_t(numbers.size()), w = all.width;
  return py::make_tuple(to_array(std::move(all), {t, h, w, 3}), numbers);
}

// A T x H x W x C float32 C-contiguous array as frames in memory (experiments/sources/sequence.h),
// read in place: `keep` holds the array until the run is done. `given`: None, or (array, name, channel
// names), the names as a file of such frames would have them (glintlab/__init__.py).
std::shared_ptr<const FrameArray> frame_array(const py::object& given, std::vector<FloatArray>& keep) {
  if (given.is_none()) return nullptr;
  const auto t = given.cast<py::tuple>();
  keep.push_back(t[0].cast<FloatArray>());
  const FloatArray& a = keep.back();
  auto out = std::make_shared<FrameArray>();
  out->name = t[1].cast<std::string>();
  out->channels = t[2].cast<std::vector<std::string>>();
  if (a.ndim() != 4 || a.shape(3) != py::ssize_t(out->channels.size()))
    throw std::invalid_argument("measure: '" + out->name + "': an array of T x H x W x " +
                                std::to_string(out->channels.size()) + " allowed");
  out->data = a.data();
  out->frames = int(a.shape(0));
  out->height = int(a.shape(1));
  out->width = int(a.shape(2));
  return out;
}

// `glintlab measure` with any input given as frames in memory: `tests` holds one entry (None or an
// array as frame_array takes it) for each of options.tests.
py::tuple measure(MeasureOptions options, const py::object& reference, const py::list& tests, const py::object& motion,
                  const py::object& depth) {
  std::vector<FloatArray> keep;
  options.reference_array = frame_array(reference, keep);
  options.motion_array = frame_array(motion, keep);
  options.depth_array = frame_array(depth, keep);
  if (tests.size() != options.tests.size()) throw std::invalid_argument("measure: one array entry per test");
  for (std::size_t i = 0; i < options.tests.size(); ++i) options.tests[i].array = frame_array(tests[i], keep);
  std::ostringstream log;
  int code = 0;
  {
    py::gil_scoped_release unlocked;
    code = measure_sequences(options, log);
  }
  return py::make_tuple(code, log.str());
}

py::tuple run(RunOptions options, const std::string& resolution) {
  std::ostringstream log;
  int code = 0;
  {
    py::gil_scoped_release unlocked;
    if (!resolution.empty())
      if (const std::string problem = set_resolution(resolution, options); !problem.empty()) throw ConfigError(problem);
    if (options.out_dir.empty()) options.out_dir = default_run_dir(options.experiment);
    code = run_experiment(options, log);
  }
  return py::make_tuple(code, log.str(), options.out_dir);
}

// `summary` and `baseline`: a file's path, or (with the flag) the JSON text of a dict.
py::list check(const std::string& summary, bool summary_is_text, const std::string& baseline, bool baseline_is_text,
               const std::vector<std::string>& tolerances) {
  std::vector<CheckRow> rows;
  {
    py::gil_scoped_release unlocked;
    const auto tol = parse_check_tolerances(tolerances);
    const nlohmann::json s = summary_is_text ? nlohmann::json::parse(summary) : read_json_file(summary);
    const nlohmann::json b = baseline_is_text ? nlohmann::json::parse(baseline) : read_json_file(baseline);
    rows = check_summary(s, b, tol, summary_is_text ? "the summary" : summary,
                         baseline_is_text ? "the baseline" : baseline);
  }
  py::list out;
  for (const CheckRow& r : rows) {
    py::dict d;
    d["variant"] = r.variant;
    d["metric"] = r.metric;
    d["baseline"] = r.baseline;
    d["current"] = r.current;
    d["change"] = r.change;
    d["tolerance"] = r.tolerance;
    d["regression"] = r.regression;
    d["skipped"] = r.skipped;
    d["note"] = r.note;
    out.append(d);
  }
  return out;
}

// Where this module was loaded from (for its data folder, core/util/data_dir.h).
std::string module_file() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&module_file), &info) == 0 || !info.dli_fname) return "";
  std::error_code ec;
  const auto real = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::string(info.dli_fname) : real.string();
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "glintlab's C++ library (use the functions of the glintlab package)";
  set_data_anchor(module_file(), 4);  // PREFIX/lib/python3/dist-packages/glintlab/_core.so

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ConfigError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const std::filesystem::filesystem_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const core::VulkanError& e) {
      PyErr_SetString(PyExc_RuntimeError, (std::string("Vulkan: ") + e.what()).c_str());
    } catch (const core::ShaderCompileError& e) {
      PyErr_SetString(PyExc_RuntimeError, (std::string("shader: ") + e.what()).c_str());
    }
  });

  py::class_<CompareOptions>(m, "CompareOptions")
      .def(py::init<>())
      .def_readwrite("space", &CompareOptions::space)
      .def_readwrite("metrics", &CompareOptions::metrics)
      .def_readwrite("ocio_config", &CompareOptions::ocio_config)
      .def_readwrite("itp_nits", &CompareOptions::itp_nits)
      .def_readwrite("view", &CompareOptions::display_view)
      .def_readwrite("threshold", &CompareOptions::threshold)
      .def_readwrite("flip_ldr", &CompareOptions::flip_ldr)
      .def_readwrite("ppd", &CompareOptions::ppd)
      .def_readwrite("monitor_distance", &CompareOptions::monitor_distance)
      .def_readwrite("monitor_width", &CompareOptions::monitor_width)
      .def_readwrite("monitor_width_pixels", &CompareOptions::monitor_width_pixels)
      .def_readwrite("tone_mapper", &CompareOptions::tone_mapper)
      .def_readwrite("start_exposure", &CompareOptions::start_exposure)
      .def_readwrite("stop_exposure", &CompareOptions::stop_exposure)
      .def_readwrite("num_exposures", &CompareOptions::num_exposures);

  py::class_<MeasureSource>(m, "MeasureSource")
      .def(py::init<>())
      .def_readwrite("name", &MeasureSource::name)
      .def_readwrite("seq", &MeasureSource::seq)
      .def_readwrite("space", &MeasureSource::space);
  py::class_<MeasureOptions>(m, "MeasureOptions")
      .def(py::init<>())
      .def_readwrite("reference", &MeasureOptions::reference)
      .def_readwrite("reference_space", &MeasureOptions::reference_space)
      .def_readwrite("tests", &MeasureOptions::tests)
      .def_readwrite("out_dir", &MeasureOptions::out_dir)
      .def_readwrite("motion", &MeasureOptions::motion)
      .def_readwrite("motion_convention", &MeasureOptions::motion_convention)
      .def_readwrite("depth", &MeasureOptions::depth)
      .def_readwrite("space", &MeasureOptions::space)
      .def_readwrite("metrics", &MeasureOptions::metrics)
      .def_readwrite("fps", &MeasureOptions::fps)
      .def_readwrite("name", &MeasureOptions::name)
      .def_readwrite("ocio_config", &MeasureOptions::ocio_config)
      .def_readwrite("display", &MeasureOptions::display)  // with view: --view DISPLAY/VIEW
      .def_readwrite("view", &MeasureOptions::view)
      .def_readwrite("report", &MeasureOptions::report);

  py::class_<RunOptions>(m, "RunOptions")
      .def(py::init([] {
        RunOptions o;
        o.validation = core::VkContext::validation_requested_by_env();
        return o;
      }))
      .def_readwrite("experiment", &RunOptions::experiment)
      .def_readwrite("out_dir", &RunOptions::out_dir)
      .def_readwrite("variants", &RunOptions::variants)
      .def_readwrite("max_frames", &RunOptions::max_frames)
      .def_readwrite("width", &RunOptions::width)
      .def_readwrite("height", &RunOptions::height)
      .def_readwrite("device", &RunOptions::device)
      .def_readwrite("report", &RunOptions::report);

  m.def("compare", &compare);
  // Test hook (tests/python): the pixel addresses the last compare read, 0 for a file.
  m.def("_last_compare_pixels", [] { return last_compare_pixels; });
  m.def("read_image", &read_image);
  m.def("read_sequence", &read_sequence);
  m.def("measure", &measure);
  m.def("run", &run);
  m.def("check", &check);
  m.def("results_path", [](const std::string& relative) { return results_path(relative); });
  m.def("data_folder", [] { return data_locations().data; });
  m.attr("__version__") = version();
  m.attr("commit") = commit();
}
