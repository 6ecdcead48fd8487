// Output files that never lose data: checked before any work, written to a
// temporary file renamed over the target only when complete, and cleaned up
// when the process is interrupted.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace detexture {

/// Check, before any work starts, that every non-empty path of `outputs` can
/// be written without losing data. Throws std::runtime_error with a sentence
/// naming the path when:
/// - it is the input (after resolving ".", "..", symbolic and hard links),
///   or two outputs are the same file;
/// - its folder does not exist or is not writable;
/// - it exists and `force` is false ("pass --force");
/// - it is a directory, a block device or a socket.
/// A character device (/dev/null) or a FIFO is accepted (with `force`, since
/// it exists) and is written through directly: it is never replaced by a
/// regular file. A symbolic link is written through too: the file it points
/// to is replaced, the link stays.
void check_output_paths(const std::vector<std::string>& outputs, const std::string& input,
                        bool force);

/// A file being written. For a regular (or not yet existing) target the bytes
/// go to a hidden temporary file in the target's folder, renamed over the
/// target by commit(); if commit() is never reached (an error, an exception)
/// the temporary file is removed and the target is untouched. A symbolic
/// link is followed: its target is the one replaced. A character device or
/// FIFO is opened and written directly. A block device or socket is refused.
/// Throws std::runtime_error naming the path when the file cannot be created.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* get() const { return file_; }
  /// Close and rename into place; throws std::runtime_error if writing failed.
  void commit();

 private:
  std::string path_;    ///< as given, for messages
  std::string target_;  ///< after following symbolic links
  std::string temp_;    ///< empty when written directly (device, FIFO)
  std::FILE* file_ = nullptr;
  int slot_ = -1;  ///< in the table of temporary files (remove_temporary_outputs)
  bool committed_ = false;
};

/// Write text to path through an OutputFile.
void write_text_file(const std::string& path, const std::string& text);

/// Remove every temporary file an OutputFile of this process is writing.
/// Async-signal-safe (only unlink on paths kept in a static table): meant for
/// a SIGINT/SIGTERM handler, which should then _exit. At most 16 outputs can
/// be open at once.
void remove_temporary_outputs() noexcept;

}  // namespace detexture
