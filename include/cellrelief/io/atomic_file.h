// SPDX-License-Identifier: MIT
/// @file atomic_file.h
/// Writing without leaving partial output: write to a temporary file beside the target, then rename
/// it over the target (atomic on POSIX file systems). If anything fails before commit(), the
/// temporary file is removed and the target is untouched.
#pragma once

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <unistd.h>

#include "cellrelief/core/error.h"

namespace cellrelief::io {

class AtomicFile {
 public:
  /// The temporary name keeps the target's extension, because writers pick the format from it.
  explicit AtomicFile(std::filesystem::path target) : mTarget(std::move(target)) {
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path dir =
        mTarget.has_parent_path() ? mTarget.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir))
      throw Error(ErrorKind::FileWrite, mTarget, "the folder does not exist");
    // Renaming over a device (/dev/null) or a folder would replace it with a plain file.
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(mTarget, ec);
    if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
      throw Error(ErrorKind::FileWrite, mTarget, "exists and is not a regular file; it is not replaced");
    mTemporary = dir / ("." + mTarget.stem().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                        std::to_string(counter++) + mTarget.extension().string());
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (!mCommitted) {
      std::error_code ec;
      std::filesystem::remove(mTemporary, ec);
    }
  }

  const std::filesystem::path& temporaryPath() const { return mTemporary; }
  const std::filesystem::path& target() const { return mTarget; }

  /// Renames the temporary file onto the target.
  void commit() {
    std::error_code ec;
    std::filesystem::rename(mTemporary, mTarget, ec);
    if (ec) throw Error(ErrorKind::FileWrite, mTarget, "cannot rename into place: " + ec.message());
    mCommitted = true;
  }

 private:
  std::filesystem::path mTarget;
  std::filesystem::path mTemporary;
  bool mCommitted = false;
};

/// Writes a text file atomically: `write(out)` fills the stream, then the file is checked and
/// renamed into place; on any failure the target is left as it was.
template <class Write>
void writeTextAtomically(const std::filesystem::path& path, Write&& write) {
  AtomicFile atomic(path);
  {
    std::ofstream out(atomic.temporaryPath(), std::ios::binary);
    if (!out) throw Error(ErrorKind::FileWrite, path, "cannot create the file");
    write(out);
    out.flush();
    if (!out) throw Error(ErrorKind::FileWrite, path, "write failed (disk full?)");
  }
  atomic.commit();
}

}  // namespace cellrelief::io
