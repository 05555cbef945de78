// SPDX-License-Identifier: MIT
/// @file paths.h
/// File-name helpers shared by the readers and writers: formats are chosen by extension.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace cellrelief::io {

/// Lower-case extension with its dot (".ply").
inline std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace cellrelief::io
