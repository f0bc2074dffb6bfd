// The one way glintlab writes a file that someone may read while it is being
// written, or that a killed run must not leave half-written: write a temporary
// file beside the target (same folder, so the rename cannot cross file
// systems), flush it, then rename it over the target. A reader sees the old
// file or the new one, never a mix; on failure the temporary is removed and
// the old file is untouched.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace glintlab {

// Calls `write(tmp_path)` to produce the temporary file, then renames it to
// `path`. Throws IoError naming the path on any failure (the exception of
// `write` propagates after the temporary is removed).
void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(const std::filesystem::path& tmp)>& write);

// Writes `bytes` to `path` atomically (as above), with fsync before the rename.
void write_text_atomic(const std::filesystem::path& path, std::string_view bytes);

// A temporary-file name beside `path`, unique per process and call.
std::filesystem::path temp_path_beside(const std::filesystem::path& path);

}  // namespace glintlab
