// SPDX-License-Identifier: MIT
/// @file test_support.h
/// Shared test helpers: where the real data lives, skipping (or, under CI, failing) when it is
/// missing, temporary folders, and reading the figures of ../shared/data/SOURCES.md.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace cellrelief::test {

inline std::filesystem::path dataDir() { return CELLRELIEF_DATA_DIR; }

/// A build that runs tens of times slower than release (sanitizers or Debug): heavy tests run a
/// smaller case there, which still reaches every code path; release runs the full one.
#if defined(__SANITIZE_ADDRESS__) || !defined(NDEBUG)
inline constexpr bool kSlowBuild = true;
#else
inline constexpr bool kSlowBuild = false;
#endif

/// Under CI (CI=true) missing data is a failure; elsewhere the test is skipped with the reason.
inline bool inCI() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

/// Skips the test (fails it under CI) when `path` does not exist.
#define CELLRELIEF_REQUIRE_FILE(path)                                                   \
  do {                                                                                  \
    if (!std::filesystem::exists(path)) {                                               \
      if (::cellrelief::test::inCI()) FAIL() << "test data missing under CI: " << (path); \
      GTEST_SKIP() << "test data not found: " << (path);                                \
    }                                                                                   \
  } while (0)

/// A fresh folder under the system temporary directory, removed with the object.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    mPath = std::filesystem::temp_directory_path() /
            ("cellrelief_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(mPath);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(mPath, ec);
  }
  const std::filesystem::path& path() const { return mPath; }
  std::filesystem::path operator/(const std::string& name) const { return mPath / name; }

 private:
  std::filesystem::path mPath;
};

inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// One row of SOURCES.md: the local path and its `key=value` figures (commas removed), plus the
/// free text of the contents column.
struct SourceRow {
  std::string path;
  std::map<std::string, long long> figures;
  std::string contents;
};

/// Rows of the data tables in SOURCES.md whose contents column has `V=` (meshes) or an image
/// description; figures such as V, F, tris, chi, comps, bnd, nm-e, nm-v, zero-area, unref, genus.
inline std::vector<SourceRow> readSources() {
  std::vector<SourceRow> rows;
  std::ifstream in(dataDir() / "SOURCES.md");
  std::string line;
  const std::regex pathRe(R"(^\| `([^`]+)` \|)");
  const std::regex figureRe(R"(([A-Za-z-]+)=(-?[0-9,]+))");
  const std::regex genusRe(R"(\*\*genus ([0-9]+)\*\*)");
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, pathRe)) continue;
    SourceRow row;
    row.path = m[1];
    // Columns: local file | path in repo | last change | bytes | contents | notes
    std::vector<std::string> cells;
    std::size_t start = 1;
    for (std::size_t bar; (bar = line.find(" | ", start)) != std::string::npos; start = bar + 3)
      cells.push_back(line.substr(start, bar - start));
    if (cells.size() >= 5) row.contents = cells[4];
    for (auto it = std::sregex_iterator(row.contents.begin(), row.contents.end(), figureRe);
         it != std::sregex_iterator(); ++it) {
      std::string value = (*it)[2];
      value.erase(std::remove(value.begin(), value.end(), ','), value.end());
      row.figures[(*it)[1]] = std::stoll(value);
    }
    if (std::regex_search(row.contents, m, genusRe)) row.figures["genus"] = std::stoll(m[1]);
    rows.push_back(row);
  }
  return rows;
}

/// The files of meshes/robustness: open, non-manifold, degenerate, flat, self-intersecting.
inline const std::vector<std::string>& robustnessMeshes() {
  static const std::vector<std::string> kMeshes{
      "bad_cube__cgal.off", "camelhead__libigl-tutorial-data.off", "degenerated__libigl-tests-data.obj",
      "degtri_four__cgal.off", "degtri_nullface__cgal.off", "degtri_sliding__cgal.off",
      "fan3__geometry-central.obj", "head_open_with_holes__cgal.off", "hourglass_ico__geometry-central.obj",
      "mech-holes-shark__cgal.off", "moebius__geometry-central.obj", "non_manifold_stitching__cgal.off",
      "non_manifold_vertex__cgal.off", "platonic_shelf__geometry-central.obj",
      "stl_box_ascii__geometry-central.stl", "stl_box_binary__geometry-central.stl",
      "triple_vierbein__geometry-central.obj", "two-boxes-bad-self-union__libigl-tests-data.ply"};
  return kMeshes;
}

/// A test name from a mesh file name: the part before "__", '-' made '_'.
inline std::string meshTestName(const testing::TestParamInfo<std::string>& info) {
  std::string name = info.param.substr(0, info.param.find("__"));
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

/// A test name from a data path: the file's stem before "__", '-' made '_'.
inline std::string testNameOfPath(const std::string& path) {
  std::string name = std::filesystem::path(path).stem().string();
  name = name.substr(0, name.find("__"));
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

/// What the command line printed and how it ended.
struct CliResult {
  int status = -1;     ///< exit status, or 128 + the signal that ended it
  std::string output;  ///< stdout and stderr together
};

/// Runs the `cellrelief` program (CELLRELIEF_CLI) with `args`, after an optional `prefix` (an
/// environment assignment, a wrapper such as xvfb-run).
inline CliResult runCli(const std::string& args, const std::string& prefix = "") {
  CliResult r;
  const std::string command = prefix + std::string(CELLRELIEF_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) r.output += buffer;
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

/// Text with every run of spaces and tabs made one space: reports align their columns with
/// padding, and a test matches the words, not the padding.
inline std::string squeezeSpaces(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool blank = c == ' ' || c == '\t';
    if (blank && !out.empty() && out.back() == ' ') continue;
    out += blank ? ' ' : c;
  }
  return out;
}

/// True when `words` appear in `text`, whatever the padding between them.
inline bool hasWords(const std::string& text, const std::string& words) {
  return squeezeSpaces(text).find(squeezeSpaces(words)) != std::string::npos;
}

}  // namespace cellrelief::test
