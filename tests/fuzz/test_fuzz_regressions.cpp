// SPDX-License-Identifier: MIT
/// Replays the fuzz seeds and every input that ever failed through the fuzz targets' code, in the
/// ordinary build: seeds are valid files and must be accepted; a regression input (named after the
/// defect it showed) must be refused with a cellrelief::Error, quickly, or accepted when its name
/// starts with "valid-". A crash, a stray exception or a stall (the CTest timeout) fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_readers.h"

namespace fs = std::filesystem;

namespace {

const fs::path kFuzzDir = CELLRELIEF_FUZZ_DIR;
const std::vector<std::string> kTargets{"obj",  "ply_ascii", "ply_binary", "off", "stl_ascii", "stl_binary",
                                        "png",  "jpeg",      "tga",        "bmp", "crm", "polycube",
                                        "polycube_map", "geotex"};

std::vector<std::uint8_t> bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The reader a target fuzzes, on these bytes.
bool readAs(const std::string& target, const std::vector<std::uint8_t>& b) {
  using namespace cellrelief::fuzz;
  if (target == "crm") return readModelBytes(b.data(), b.size(), false);
  if (target == "geotex") return readGeoTexBytes(b.data(), b.size(), false);
  if (target == "polycube") return readPolycubeBytes(b.data(), b.size());
  if (target == "polycube_map") return readPolycubeMapBytes(b.data(), b.size());
  const std::string ext = target.substr(0, target.find('_'));
  if (target == "png" || target == "jpeg" || target == "tga" || target == "bmp")
    return readImageBytes(target == "jpeg" ? ".jpg" : "." + ext, b.data(), b.size());
  return readMeshBytes("." + ext, b.data(), b.size());
}

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

class FuzzTarget : public testing::TestWithParam<std::string> {};

TEST_P(FuzzTarget, EverySeedIsAcceptedAndSmall) {
  const std::vector<fs::path> seeds = filesIn(kFuzzDir / "corpus" / GetParam());
  ASSERT_GE(seeds.size(), 1u) << "no seeds for " << GetParam();
  for (const fs::path& seed : seeds) {
    EXPECT_LE(fs::file_size(seed), 8192u) << seed << ": seeds stay under the targets' -max_len";
    EXPECT_TRUE(readAs(GetParam(), bytesOf(seed))) << seed << " is a seed the reader refuses";
  }
}

TEST_P(FuzzTarget, EveryInputThatEverFailedIsHandled) {
  for (const fs::path& input : filesIn(kFuzzDir / "regressions" / GetParam())) {
    const bool valid = input.filename().string().starts_with("valid-");
    EXPECT_EQ(readAs(GetParam(), bytesOf(input)), valid) << input;
  }
}

TEST_P(FuzzTarget, TruncatedSeedsAreRefusedWhereTheFormatCanTell) {
  // Every prefix of a seed in steps: the cheapest mutation, and the one real files suffer most.
  // Formats that state their length (PNG chunks and CRCs, binary PLY and STL counts, the model's
  // section sizes) must refuse every proper prefix (a PNG every one that cuts into its pixel data:
  // without its 12-byte end chunk the image is whole); a prefix of a text file or of a TGA, BMP or
  // JPEG can still be a readable file, so there only the empty prefix must be refused.
  const std::string target = GetParam();
  const bool sized = target == "png" || target == "crm" || target == "geotex" || target == "ply_binary" || target == "stl_binary";
  for (const fs::path& seed : filesIn(kFuzzDir / "corpus" / target)) {
    const std::vector<std::uint8_t> whole = bytesOf(seed);
    const std::size_t step = std::max<std::size_t>(1, whole.size() / 64);
    for (std::size_t n = 0; n < whole.size(); n += step) {
      const bool read = readAs(target, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
      const bool cutsData = target != "png" || n + 12 < whole.size();
      if (n == 0 || (sized && cutsData)) EXPECT_FALSE(read) << seed << " cut to " << n << " bytes was accepted";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzTarget, testing::ValuesIn(kTargets),
                         [](const testing::TestParamInfo<std::string>& target) { return target.param; });

}  // namespace
