// The data table of a glint model that declares one ("// glint_table size=N",
// shaders/glint/query.glsl): entry i is the model file's own
// glint_table_entry(i), evaluated once on the device by shaders/glint/
// table.comp. Tables are kept by the content hash of that program (the
// preprocessed source with every include and the defines): in memory for the
// process, and as <dir>/glint-tables/<hash>.f32 where a cache folder is set.
// A table with a NaN or Inf entry is refused, naming the
// model's file and the entry.
#pragma once

#include "core/material/glint_model.h"
#include "core/vk/vk_context.h"

#include <memory>
#include <string>
#include <vector>

namespace glintlab::core {

// The model's table (table_size floats); an empty table when it declares none.
std::shared_ptr<const std::vector<float>> glint_table(const VkContext& ctx, const GlintModelDecl& d);

// Where tables are kept on disk ("" = in memory only); the runner sets its cache folder.
void set_glint_table_cache_dir(const std::string& dir);

}  // namespace glintlab::core
