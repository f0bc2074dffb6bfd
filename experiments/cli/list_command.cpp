// `glintlab list`: what is built in (experiments, paths, scenes, presets,
// debug outputs, glint models, TAA resolves, metrics, motion conventions) and the Vulkan devices.
#include "core/material/glint_model.h"
#include "core/render/taa_resolve.h"
#include "core/material/sand_material.h"
#include "core/scene/camera_path.h"
#include "core/vk/vk_context.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/sources/motion_convention.h"
#include "experiments/spec/experiment_spec.h"
#include "core/util/json_check.h"
#include "metrics/metric_registry.h"

#include <iostream>

namespace glintlab {

namespace {

// "  —  " and the first sentence of a built-in experiment's "description" (at most 110 characters), or
// "" where it has none (or cannot be read: `list` lists what is there).
std::string experiment_summary_line(const std::string& name) {
  try {
    const nlohmann::json j = read_json_file(resolve_experiment_path(name));
    std::string d = j.is_object() && j.contains("description") && j["description"].is_string()
                        ? j["description"].get<std::string>()
                        : "";
    for (size_t i = d.find(". "); i != std::string::npos; i = d.find(". ", i + 1))  // a sentence ends before
      if (i + 2 < d.size() && d[i + 2] >= 'A' && d[i + 2] <= 'Z') {                // a capital ("Fig. 6" goes on)
        d.resize(i);
        break;
      }
    if (!d.empty() && d.back() == '.') d.pop_back();
    if (d.size() > 110) d = d.substr(0, 107) + "...";
    return d.empty() ? "" : "  -  " + d;
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

void add_list_command(CLI::App& app, int& exit_code) {
  CLI::App* list = app.add_subcommand("list", "list built-in experiments, camera paths, presets, metrics, devices");
  list->callback([&exit_code] {
    exit_code = run_guarded(
        [] {
          auto print = [](const char* title, const std::vector<std::string>& xs) {
            std::cout << title << ":\n";
            for (const auto& x : xs) std::cout << "  " << x << "\n";
          };
          std::cout << "experiments:\n";
          for (const auto& name : builtin_experiment_names())
            std::cout << "  " << name << experiment_summary_line(name) << "\n";
          print("camera paths", core::CameraPath::builtin_names());
          print("scenes (mesh types)", {"plane", "wavy", "sphere", "dunes"});
          print("material presets", core::SandParams::preset_names());
          print("glint models", core::glint_model_names());
          print("TAA resolves (\"taa\": {\"name\": ...}, taa-test)", core::taa_resolve_names());
          print("debug outputs", core::SandParams::debug_output_names());
          print("metrics", metrics::metric_names());
          print("metric groups", metrics::metric_group_names());
          print("motion conventions (measure --motion-convention)", enum_names(kMotionConventionNames));
          std::cout << "devices:\n";
          for (const auto& d : core::VkContext::list_devices())
            std::cout << "  " << d.index << ": " << d.name << " (" << d.type << ", Vulkan " << d.api_version << ")\n";
          return kExitOk;
        },
        std::cerr);
  });
}

}  // namespace glintlab
