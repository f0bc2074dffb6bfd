// The manual agrees with the program: every relative link of every README resolves, and every
// command's --help lists the options of the README's command block (and the README states the
// defaults the help states), so the two cannot drift apart.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = GLINTLAB_SOURCE_DIR;

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string help_of(const std::string& command) {
  std::string out;
  FILE* p = popen((std::string(GLINTLAB_CLI) + " " + command + " --help 2>&1").c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  pclose(p);
  return out;
}

std::vector<fs::path> readmes() {
  std::vector<fs::path> out;
  for (auto it = fs::recursive_directory_iterator(kRoot); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name == "build" || name == ".git" || name.rfind("build", 0) == 0 || name == "cache")) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && name == "README.md") out.push_back(it->path());
  }
  return out;
}

// An option line of CLI11's help: "  -h,--help", "  --ppd,--pixels-per-degree FLOAT  text".
struct HelpOption {
  std::vector<std::string> names;
  std::string default_text;  // what "(default: X)" / "(default X)" / "X (default)" says, or ""
};

std::vector<HelpOption> help_options(const std::string& help) {
  std::vector<HelpOption> out;
  static const std::regex line_re(R"(^\s+((?:-[A-Za-z],)?--[a-z0-9-]+(?:,--[a-z0-9-]+)*)(.*)$)");
  static const std::regex def_re(R"(\(default:? (.*)\)\s*$)"), word_def_re(R"((\w+) \((?:[^()]*, )?default\))");
  std::istringstream in(help);
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, line_re)) continue;
    HelpOption o;
    std::stringstream names(m[1].str());
    std::string n;
    while (std::getline(names, n, ','))
      if (n.rfind("--", 0) == 0) o.names.push_back(n);
    const std::string rest = m[2];
    std::smatch d;
    if (std::regex_search(rest, d, def_re)) o.default_text = d[1];
    else if (std::regex_search(rest, d, word_def_re)) o.default_text = d[1];
    if (o.names != std::vector<std::string>{"--help"}) out.push_back(o);
  }
  return out;
}

// The README's "## Commands" code block: command -> the --options of its lines.
std::map<std::string, std::set<std::string>> readme_commands(const std::string& readme) {
  std::map<std::string, std::set<std::string>> out;
  const size_t at = readme.find("## Commands");
  const size_t open = readme.find("```", at), close = readme.find("```", open + 3);
  std::istringstream in(readme.substr(open + 3, close - open - 3));
  std::string line, current;
  static const std::regex cmd_re(R"(^glintlab ([a-z][a-z-]*)\b)"), opt_re(R"(--[a-z0-9-]+)");
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, cmd_re)) current = m[1];
    else if (line.empty() || line[0] != ' ') current.clear();  // another program's line (the bench, a script)
    if (current.empty()) continue;
    out[current];
    // Options only outside the trailing "(...)" remark of a line.
    const std::string body = line.substr(0, line.find("  ("));
    for (auto it = std::sregex_iterator(body.begin(), body.end(), opt_re); it != std::sregex_iterator(); ++it)
      out[current].insert(it->str());
  }
  return out;
}

}  // namespace

TEST(Docs, EveryRelativeLinkOfEveryReadmeResolves) {
  static const std::regex link_re(R"(\]\(([^)\s]+)\))");
  size_t links = 0;
  const auto files = readmes();
  ASSERT_GE(files.size(), 5u);
  for (const fs::path& f : files) {
    const std::string text = read_text(f);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link_re); it != std::sregex_iterator(); ++it) {
      std::string target = (*it)[1];
      if (target.rfind("http", 0) == 0 || target.rfind("mailto:", 0) == 0 || target[0] == '#') continue;
      target = target.substr(0, target.find('#'));
      ++links;
      EXPECT_TRUE(fs::exists(f.parent_path() / target)) << f << ": the link " << target << " does not resolve";
    }
  }
  EXPECT_GE(links, 5u);
}

TEST(Docs, EveryCommandsHelpListsTheReadmesOptionsAndDefaults) {
  const std::string readme = read_text(kRoot / "README.md");
  const auto block = readme_commands(readme);
  const std::vector<std::string> commands = {"run", "render", "merge", "measure", "report", "check",
                                             "compare", "stress", "tune", "list", "glint-test"};
  for (const std::string& c : commands) {
    ASSERT_TRUE(block.count(c)) << "the README's command block has no line for `glintlab " << c << "`";
    const std::vector<HelpOption> help = help_options(help_of(c));
    const std::set<std::string>& documented = block.at(c);
    std::set<std::string> known;
    for (const HelpOption& o : help) {
      bool listed = false;
      for (const std::string& n : o.names) {
        known.insert(n);
        listed = listed || documented.count(n);
      }
      EXPECT_TRUE(listed) << "`glintlab " << c << " --help` has " << o.names[0] << ", the README's command block does not";
      // A default the help states is stated in the README's "Defaults" list, on the command's line.
      if (o.default_text.empty()) continue;
      bool stated = false;
      const size_t from = readme.find("### Defaults");
      ASSERT_NE(from, std::string::npos) << "the README has no \"### Defaults\" list";
      const size_t to = readme.find("\n#", from + 4);
      std::istringstream in(readme.substr(from, to == std::string::npos ? std::string::npos : to - from));
      std::string line;
      while (std::getline(in, line)) {
        if (line.find("`" + c + "`") == std::string::npos) continue;
        for (const std::string& n : o.names)
          stated = stated || line.find("`" + n + "` " + o.default_text) != std::string::npos;
      }
      EXPECT_TRUE(stated) << "`glintlab " << c << " --help` says " << o.names[0] << " defaults to \"" << o.default_text
                          << "\"; the README's Defaults list does not say so on `" << c << "`'s line";
    }
    for (const std::string& n : documented)
      EXPECT_TRUE(known.count(n)) << "the README lists " << n << " for `glintlab " << c << "`; its --help does not";
  }
}

namespace {

// The source and documentation files whose comments and text name repository paths.
std::vector<fs::path> documented_files() {
  static const std::set<std::string> kExt = {".h", ".cpp", ".glsl", ".comp", ".frag", ".vert", ".py", ".sh", ".md"};
  std::vector<fs::path> out;
  for (auto it = fs::recursive_directory_iterator(kRoot); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    const fs::path rel = fs::relative(it->path(), kRoot);
    if (it->is_directory() && (name == ".git" || name.rfind("build", 0) == 0 || name == "cache" ||
                               rel == "tests/data" || rel == "tests/fuzz/corpus" || rel == "results")) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && (kExt.count(it->path().extension().string()) || name == "CMakeLists.txt"))
      out.push_back(it->path());
  }
  return out;
}

// What a reader reads of a file: a README whole; of code, its comments (// and # to the line's end).
std::string prose_of(const fs::path& f) {
  const std::string text = read_text(f);
  if (f.extension() == ".md") return text;
  const bool hash = f.extension() == ".py" || f.extension() == ".sh" || f.filename() == "CMakeLists.txt";
  std::string out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const size_t at = line.find(hash ? "#" : "//");
    if (at != std::string::npos) out += line.substr(at) + "\n";
  }
  return out;
}

}  // namespace

// Every repository path a README or a code comment names exists (relative to the repository, to the
// file's folder, or to shaders/ for shader names), and none points outside the repository.
TEST(Docs, EveryPathNamedInAReadmeOrACommentExists) {
  static const std::regex path_re(
      R"((?:^|[^\w/.-])((?:core|experiments|shaders|metrics|tests|docs)/[A-Za-z0-9_./+-]*[A-Za-z0-9_]))");
  static const std::set<std::string> kExt = {".h", ".cpp", ".glsl", ".comp", ".frag", ".vert", ".py",
                                             ".sh", ".md", ".json", ".png", ".txt"};
  size_t paths = 0;
  for (const fs::path& f : documented_files()) {
    const std::string prose = prose_of(f);
    for (const char* outside : {"DESIGN.md", "../shared", "TOOLCHAIN-FACTS", "ANCHORS.md", "STYLE.md"})
      EXPECT_EQ(prose.find(outside), std::string::npos) << f << " points outside the repository: " << outside;
    for (auto it = std::sregex_iterator(prose.begin(), prose.end(), path_re); it != std::sregex_iterator(); ++it) {
      const std::string p = (*it)[1];
      const size_t end = size_t(it->position(1) + it->length(1));
      if (end < prose.size() && std::string("<*%#{").find(prose[end]) != std::string::npos) continue;  // a pattern
      if (!kExt.count(fs::path(p).extension().string())) continue;  // a folder or a word, not a file
      ++paths;
      EXPECT_TRUE(fs::exists(kRoot / p) || fs::exists(f.parent_path() / p) || fs::exists(kRoot / "shaders" / p))
          << fs::relative(f, kRoot) << " names " << p << ", which does not exist";
    }
  }
  EXPECT_GE(paths, 100u);
}
