#include "experiments/runner/plan.h"

#include "core/util/content_hash.h"
#include "core/vk/shader_compiler.h"
#include "experiments/sources/variant_factory.h"

#include <algorithm>
#include <filesystem>

namespace glintlab {

RunPlan make_plan(const ExperimentSpec& spec, int frames, bool measure, const metrics::ColorManager& cm,
                  const SceneData& scene, const std::string& device_name, std::ostream* log) {
  std::ostringstream quiet;
  std::ostream& note = log ? *log : quiet;
  auto open_files = [&](const std::string& seq, const std::string& space, const std::string& what) {
    int w = spec.width, h = spec.height;
    return open_colour_sequence(seq, first_frame_numbers(seq, frames, what), space, cm, what, &w, &h, note);
  };
  RunPlan plan;
  plan.spec = &spec;
  plan.frames = frames;
  plan.measure = measure;
  std::vector<std::string> ref_keys;
  for (const VariantSpec& v : spec.variants) {
    RunPlan::Variant pv;
    pv.spec = &v;
    pv.params = to_working_space(v.material, spec.working_space, cm);
    core::SandFeatures needs = scene.range;
    needs.debug_output = v.debug;
    if (v.frames.empty())
      pv.program = core::sand_program(pv.params, needs, core::ProgramRole::Variant);
    else
      pv.files = open_files(v.frames, v.frames_space, spec.file + ": variant " + v.name + ": frames");
    if (measure && !spec.reference.frames.empty()) {  // one reference read from files for every variant
      if (plan.references.empty()) {
        plan.references.push_back({"reference", {}, "frames:" + spec.reference.frames, {}, std::nullopt});
        plan.references[0].files =
            open_files(spec.reference.frames, spec.reference.frames_space, spec.file + ": reference: frames");
      }
      pv.reference = 0;
      plan.references[0].variants.push_back(int(plan.variants.size()));
    } else if (measure) {
      pv.truth_params = v.truth_material ? to_working_space(*v.truth_material, spec.working_space, cm) : pv.params;
      core::MaterialProgram ref = core::sand_program(pv.truth_params, needs, core::ProgramRole::Reference);
      const std::string key = ref.cache_key();
      auto it = std::find(ref_keys.begin(), ref_keys.end(), key);
      if (it == ref_keys.end()) {
        ref_keys.push_back(key);
        plan.references.push_back({"", ref, key, {}, std::nullopt});
        it = ref_keys.end() - 1;
      }
      pv.reference = int(it - ref_keys.begin());
      plan.references[size_t(pv.reference)].variants.push_back(int(plan.variants.size()));
    }
    plan.variants.push_back(std::move(pv));
  }
  // Names: "reference" alone; else by the truth's glint model ("reference-grains"), and by the first
  // variant where two references share a model.
  auto model_of = [&](const RunPlan::Reference& r) {
    const core::SandParams truth = plan.variants[size_t(r.variants.front())].truth_params.reference();
    // a user's model file by its file name without the extension
    return truth.glint_file ? std::filesystem::path(truth.glint_model).stem().string() : truth.glint_model;
  };
  for (auto& r : plan.references) {
    int same_model = 0;
    for (const auto& o : plan.references) same_model += model_of(o) == model_of(r);
    r.name = plan.references.size() == 1 ? "reference"
             : same_model == 1           ? "reference-" + model_of(r)
                                         : "reference-" + plan.variants[size_t(r.variants.front())].spec->name;
  }
  // Each truth writes the folders NAME, NAME-half-a and NAME-half-b: no two truths may share one (a user's
  // model file named "kajs-half-a.glsl" would write into the Kajs truth's half A). A truth whose folders
  // meet an earlier one's is numbered instead, "reference-K", K the first count that meets none.
  auto folders = [](const std::string& n) { return std::vector<std::string>{n, n + "-half-a", n + "-half-b"}; };
  auto meets = [&](size_t i) {
    for (size_t j = 0; j < plan.references.size(); ++j)
      for (const auto& a : folders(plan.references[i].name))
        for (const auto& b : folders(plan.references[j].name))
          if (j != i && a == b) return true;
    return false;
  };
  int next = 1;
  for (size_t i = plan.references.size(); i-- > 0;)  // the later truth takes the number
    while (meets(i)) plan.references[i].name = "reference-" + std::to_string(next++);

  core::ContentHash h;
  // v4: supersampled passes (supersampling()); v5: the mesh itself (an adaptive grid depends on
  // the camera path and the resolution, not only on the scene's keys)
  h.add(std::string_view("glintlab-reference-v5"))
      .add(int64_t(kReferencePatternSeed))
      .add(spec.source.at("scene").dump())
      .add(spec.working_space)
      .add(std::string_view(device_name))
      .add(int64_t(spec.width))
      .add(int64_t(spec.height))
      .add(int64_t(spec.reference.grid))
      .add(scene.env_texture.mips_rgba[0].data(), scene.env_texture.mips_rgba[0].size() * 4)
      .add(scene.env.sh_irradiance.data(), sizeof scene.env.sh_irradiance)
      .add(scene.mesh.vertices.data(), scene.mesh.vertices.size() * sizeof(core::Vertex))
      .add(scene.mesh.indices.data(), scene.mesh.indices.size() * sizeof(uint32_t))
      .add(core::default_shader_compiler().source_hash("passes/surface.vert", core::ShaderStage::Vertex))
      .add(core::default_shader_compiler().source_hash("passes/sky.frag", core::ShaderStage::Fragment));
  plan.scene_key = h.hex();
  return plan;
}

std::string RunPlan::reference_key(int r, const core::FrameUniforms& fu) const {
  // The frame's content is all in its uniforms (camera, previous camera, model
  // matrices, sun, sky); the time stamp is not read by any shader, so frames
  // that look the same (a static camera) share one entry.
  core::FrameUniforms u = fu;
  u.camera_pos.w = 0.0f;
  core::ContentHash h;
  h.add(std::string_view(scene_key)).add(std::string_view(references.at(size_t(r)).program_key)).add(&u, sizeof u);
  return h.hex();
}

}  // namespace glintlab
