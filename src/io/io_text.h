// Internal: error messages and line-by-line scanning shared by the readers.
#pragma once

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace detexture::io_detail {

/// "cannot read 'path': where: what" — one line, as the CLI prints it.
[[noreturn]] inline void throw_read_error(const std::string& path, const std::string& where,
                                          const std::string& what) {
  throw std::runtime_error("cannot read '" + path + "': " + (where.empty() ? "" : where + ": ") +
                           what);
}

[[noreturn]] inline void throw_write_error(const std::string& path, const std::string& what) {
  throw std::runtime_error("cannot write '" + path + "': " + what);
}

inline std::string at_line(std::size_t line) { return "line " + std::to_string(line); }
inline std::string at_byte(std::size_t offset) { return "byte " + std::to_string(offset); }

/// Walks text one line at a time; accepts "\n", "\r\n" and lone "\r"
/// (old Mac) line endings, in any mix.
class TextLines {
 public:
  /// text starts at line first_line (1-based) of the file.
  TextLines(std::string_view text, std::size_t first_line)
      : text_(text), next_line_(first_line), line_(first_line - 1) {}

  /// The next line without its ending; false at the end of the text.
  bool next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    const char* start = text_.data() + pos_;
    // The next '\n' is searched once and remembered, so that a file with
    // lone '\r' endings is not rescanned to its end for every line.
    if (!newline_known_ || newline_ < pos_) {
      newline_known_ = true;
      const void* nl = std::memchr(start, '\n', text_.size() - pos_);
      newline_ =
          nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - text_.data()) : text_.size();
    }
    std::size_t end = newline_;
    const void* cr = std::memchr(start, '\r', newline_ - pos_);
    if (cr) end = static_cast<std::size_t>(static_cast<const char*>(cr) - text_.data());
    const std::size_t length = end - pos_;
    if (end == text_.size())
      pos_ = end;
    else if (text_[end] == '\r' && end + 1 < text_.size() && text_[end + 1] == '\n')
      pos_ = end + 2;
    else
      pos_ = end + 1;
    *line = std::string_view(start, length);
    line_ = next_line_++;
    return true;
  }

  /// Number of the line last returned by next() (first_line - 1 before the first).
  std::size_t line() const { return line_; }
  /// Offset just past the line last returned by next().
  std::size_t position() const { return pos_; }
  std::size_t bytes_left() const { return text_.size() - pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t newline_ = 0;  ///< offset of the next '\n' (or the end), once known
  bool newline_known_ = false;
  std::size_t next_line_;
  std::size_t line_;
};

inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Split line at runs of spaces and tabs into *tokens (cleared first).
inline void split_whitespace(std::string_view line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) tokens->push_back(line.substr(start, i - start));
  }
}

}  // namespace detexture::io_detail
