#include "detexture/io/output_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>
#include <system_error>

#include "io_text.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;
using io_detail::throw_write_error;

// The temporary files being written, for remove_temporary_outputs(), which
// runs in a signal handler: fixed buffers and lock-free flags only.
constexpr int kSlots = 16;
constexpr std::size_t kPathBytes = 4096;
char g_paths[kSlots][kPathBytes];
std::atomic<int> g_used[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need lock-free flags");

int register_temporary(const std::string& path) {
  if (path.size() >= kPathBytes) return -1;  // not removed on a signal; still removed on errors
  for (int s = 0; s < kSlots; ++s) {
    if (g_used[s].load() != 0) continue;
    std::memcpy(g_paths[s], path.c_str(), path.size() + 1);
    g_used[s].store(1);
    return s;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_used[slot].store(0);
}

// The file a path finally names, following symbolic links (also dangling
// ones: writing creates their target rather than replacing the link).
fs::path follow_links(const fs::path& path) {
  fs::path p = path;
  for (int depth = 0; depth < 40; ++depth) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) return p;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  return p;
}

fs::path folder_of(const fs::path& file) {
  return file.parent_path().empty() ? fs::path(".") : file.parent_path();
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec) && !ec) return true;
  const fs::path ca = fs::weakly_canonical(follow_links(a), ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(follow_links(b), ec);
  return !ec && ca == cb;
}

bool written_directly(const fs::file_status& status) {
  return fs::is_character_file(status) || fs::is_fifo(status);
}

}  // namespace

void check_output_paths(const std::vector<std::string>& outputs, const std::string& input,
                        bool force) {
  std::vector<std::string> checked;
  for (const std::string& out : outputs) {
    if (out.empty()) continue;
    const fs::path target = follow_links(out);
    std::error_code ec;
    const fs::file_status status = fs::status(target, ec);
    const bool exists = fs::exists(status);
    if (fs::is_directory(status)) throw_write_error(out, "it is a directory");
    if (fs::is_block_file(status) || fs::is_socket(status))
      throw_write_error(out, "it is a block device or a socket; refusing to write to it");
    if (!input.empty() && same_file(out, input))
      throw_write_error(out, "it is the input file '" + input +
                                 "'; refusing to overwrite it, choose another output path");
    for (const std::string& other : checked)
      if (same_file(out, other) && !fs::is_character_file(status))
        throw_write_error(out, "it is also given as the output '" + other +
                                   "'; one would overwrite the other, choose two paths");
    if (exists && !force) throw_write_error(out, "it exists; pass --force to overwrite it");
    if (written_directly(status)) {
      if (access(target.c_str(), W_OK) != 0)
        throw_write_error(out,
                          std::string("it cannot be opened for writing: ") + std::strerror(errno));
    } else {
      const fs::path folder = folder_of(target);
      if (!fs::is_directory(folder, ec))
        throw_write_error(out, "the folder '" + folder.string() + "' does not exist");
      if (access(folder.c_str(), W_OK | X_OK) != 0)
        throw_write_error(out, "the folder '" + folder.string() + "' is not writable");
      if (!target.has_filename()) throw_write_error(out, "the path names no file");
    }
    checked.push_back(out);
  }
}

OutputFile::OutputFile(const std::string& path) : path_(path) {
  const fs::path target = follow_links(path);
  target_ = target.string();
  std::error_code ec;
  const fs::file_status status = fs::status(target, ec);
  if (fs::is_directory(status)) throw_write_error(path, "it is a directory");
  if (fs::is_block_file(status) || fs::is_socket(status))
    throw_write_error(path, "it is a block device or a socket; refusing to write to it");
  if (written_directly(status)) {
    // A device or FIFO: renaming a file over it would replace it.
    file_ = std::fopen(target_.c_str(), "wb");
    if (!file_) throw_write_error(path, std::string("cannot open it: ") + std::strerror(errno));
    return;
  }
  if (!target.has_filename()) throw_write_error(path, "the path names no file");
  const fs::path folder = folder_of(target);
  std::random_device device;
  std::mt19937_64 rng((std::uint64_t(device()) << 32) ^ device());
  for (int attempt = 0; attempt < 100 && !file_; ++attempt) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(rng()));
    temp_ = (folder / ("." + target.filename().string() + suffix)).string();
    slot_ = register_temporary(temp_);
    // "x": fail rather than reuse a file that exists (C11, glibc).
    file_ = std::fopen(temp_.c_str(), "wbx");
    const int error = errno;
    if (!file_) {
      unregister_temporary(slot_);
      slot_ = -1;
      if (error != EEXIST) {
        errno = error;
        break;
      }
    }
  }
  if (!file_)
    throw_write_error(path,
                      "cannot create a file in " + folder.string() + ": " + std::strerror(errno));
}

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temp_.empty()) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
  unregister_temporary(slot_);
}

void OutputFile::commit() {
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!closed) throw_write_error(path_, std::string("writing failed: ") + std::strerror(errno));
  if (!temp_.empty()) {
    std::error_code ec;
    fs::rename(temp_, target_, ec);
    if (ec) throw_write_error(path_, "cannot replace the file: " + ec.message());
  }
  committed_ = true;
  unregister_temporary(slot_);
  slot_ = -1;
}

void write_text_file(const std::string& path, const std::string& text) {
  OutputFile file(path);
  if (std::fwrite(text.data(), 1, text.size(), file.get()) != text.size())
    throw_write_error(path, std::string("writing failed: ") + std::strerror(errno));
  file.commit();
}

void remove_temporary_outputs() noexcept {
  for (int s = 0; s < kSlots; ++s)
    if (g_used[s].load() != 0) unlink(g_paths[s]);
}

}  // namespace detexture
