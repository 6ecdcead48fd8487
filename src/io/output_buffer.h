// Internal: buffered output to an open file that reports failures as
// exceptions naming the target path.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "io_text.h"

namespace detexture::io_detail {

class OutputBuffer {
 public:
  /// file must stay open while the buffer is used; path names the target in errors.
  OutputBuffer(std::FILE* file, const std::string& path) : file_(file), path_(path) {
    buffer_.reserve(kFlushBytes + 4096);
  }

  /// Append to this, then call maybe_flush() once in a while (after each row).
  std::string& text() { return buffer_; }

  void append(const void* data, std::size_t size) {
    buffer_.append(static_cast<const char*>(data), size);
  }

  void maybe_flush() {
    if (buffer_.size() >= kFlushBytes) flush();
  }

  void flush() {
    if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
      throw_write_error(path_, std::string("writing failed: ") + std::strerror(errno));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kFlushBytes = std::size_t(1) << 20;
  std::FILE* file_;
  const std::string& path_;
  std::string buffer_;
};

}  // namespace detexture::io_detail
