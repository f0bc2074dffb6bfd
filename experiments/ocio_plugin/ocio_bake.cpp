// glintlab_ocio_bake CONFIG OUT.cpp: asks OpenColorIO (through libglintlab_ocio.so) what a ColorManager
// needs of CONFIG and writes it as C++, the definition of metrics::compiled_bake()
// (metrics/color/color_bake.h). The build runs it on the shipped config; the program compiles the result.
#include "core/util/atomic_file.h"
#include "core/util/content_hash.h"
#include "core/util/ocio_plugin.h"
#include "core/util/strings.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

extern char** environ;

namespace {

using glintlab::ocio::MatrixStep;

// A C++ string literal of s (the config's names are printable ASCII; anything else is escaped).
std::string literal(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += char(c);
    else if (c >= 0x20 && c < 0x7f) out += char(c);
    else {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\%03o", unsigned(c));
      out += esc;
    }
  }
  return out + "\"";
}

// A double as a hexadecimal floating literal: the exact value OpenColorIO holds.
std::string exact(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

std::string bake_source(const std::string& config_path) {
  const std::optional<std::string> bytes = glintlab::read_text_file(config_path);
  if (!bytes) throw std::runtime_error("OCIO config '" + config_path + "': cannot be read");
  std::unique_ptr<glintlab::ocio::Config> config = glintlab::ocio::api().load(config_path);

  std::map<std::string, std::string> names;  // sorted, one entry per lower-case name
  for (const auto& [name, canonical] : config->names()) names.emplace(glintlab::ascii_lower(name), canonical);

  std::string steps, conversions;
  int n_steps = 0, n_conversions = 0;
  const std::vector<std::string> spaces = config->spaces();
  for (const std::string& from : spaces)
    for (const std::string& to : spaces) {
      std::vector<MatrixStep> found;
      if (from == to || !config->matrix_steps(from, to, found)) continue;
      conversions += "    {" + literal(from) + ", " + literal(to) + ", kSteps + " + std::to_string(n_steps) + ", " +
                     std::to_string(found.size()) + "},\n";
      for (const MatrixStep& s : found) {
        steps += "    {{{";
        for (std::size_t i = 0; i < s.m.size(); ++i) steps += (i ? ", " : "") + exact(s.m[i]);
        steps += "}}, {{";
        for (std::size_t i = 0; i < s.offset.size(); ++i) steps += (i ? ", " : "") + exact(s.offset[i]);
        steps += "}}},\n";
        ++n_steps;
      }
      ++n_conversions;
    }
  std::string name_rows;
  for (const auto& [name, canonical] : names) name_rows += "    {" + literal(name) + ", " + literal(canonical) + "},\n";

  const std::string file = std::filesystem::path(config_path).filename().string();
  std::string out;
  out += "// Written by glintlab_ocio_bake from " + file + " (metrics/color/color_bake.h): OpenColorIO's answers.\n";
  out += "#include \"metrics/color/color_bake.h\"\n\nnamespace glintlab::metrics {\nnamespace {\n\n";
  out += "const ocio::MatrixStep kSteps[] = {\n" + (steps.empty() ? "    {},\n" : steps) + "};\n\n";
  out += "const BakedConversion kConversions[] = {\n" + conversions + "};\n\n";
  out += "const BakedName kNames[] = {\n" + name_rows + "};\n\n}  // namespace\n\n";
  out += "const BakedConfig& compiled_bake() {\n  static const BakedConfig bake{" +
         literal(glintlab::core::hash_hex(*bytes)) + ", kNames, " + std::to_string(names.size()) + ", kConversions, " +
         std::to_string(n_conversions) + "};\n  return bake;\n}\n\n}  // namespace glintlab::metrics\n";
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"write OpenColorIO's answers for a config as C++ (metrics/color/color_bake.h)"};
  std::string config, out;
  app.add_option("config", config, "the OCIO config file")->required()->check(CLI::ExistingFile);
  app.add_option("out", out, "the C++ file to write")->required();
  CLI11_PARSE(app, argc, argv);
  // OpenColorIO's answers without the variables that change them (the bake is used only without them).
  std::vector<std::string> set;
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, "OCIO_", 5) == 0) set.emplace_back(*e, std::strcspn(*e, "="));
  for (const std::string& name : set) ::unsetenv(name.c_str());
  try {
    glintlab::write_text_atomic(out, bake_source(config));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "glintlab_ocio_bake: %s\n", e.what());
    return 2;
  }
}
