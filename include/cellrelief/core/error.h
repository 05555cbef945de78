// SPDX-License-Identifier: MIT
/// @file error.h
/// Error types. Every error says what went wrong and, when a file is involved, which file, so that a
/// command line can print `what()` as is and exit non-zero. Exceptions rather than codes because the
/// failures (bad files, bad parameters) happen far from where they can be handled.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

namespace cellrelief {

/// What kind of failure an Error reports; lets callers branch without parsing messages.
enum class ErrorKind {
  InvalidArgument,  ///< a parameter out of its range (N = 0, an empty mesh, ...)
  InvalidInput,     ///< data that cannot be used (NaN coordinates, indices out of range, ...)
  FileNotFound,     ///< the path does not exist or cannot be opened
  FileFormat,       ///< the bytes are not a valid file of the expected format
  FileWrite,        ///< an output file could not be written
  Unsupported,      ///< a valid request this build or platform cannot serve
  ResourceLimit,    ///< the request would exceed a memory or size limit
};

inline const char* toString(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::InvalidArgument: return "invalid argument";
    case ErrorKind::InvalidInput: return "invalid input";
    case ErrorKind::FileNotFound: return "file not found";
    case ErrorKind::FileFormat: return "bad file format";
    case ErrorKind::FileWrite: return "cannot write file";
    case ErrorKind::Unsupported: return "unsupported";
    case ErrorKind::ResourceLimit: return "resource limit";
  }
  return "error";
}

/// The library's exception. `what()` reads "<path>: <problem>" when a file is involved.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& problem)
      : std::runtime_error(problem), mKind(kind), mProblem(problem) {}
  Error(ErrorKind kind, const std::filesystem::path& path, const std::string& problem)
      : std::runtime_error(path.string() + ": " + problem),
        mKind(kind),
        mPath(path),
        mProblem(problem) {}

  ErrorKind kind() const { return mKind; }
  /// The file concerned; empty when the error is not about a file.
  const std::filesystem::path& path() const { return mPath; }
  /// The problem alone, without the path.
  const std::string& problem() const { return mProblem; }

 private:
  ErrorKind mKind;
  std::filesystem::path mPath;
  std::string mProblem;
};

}  // namespace cellrelief
