#include "detexture/tiling/tile_bins.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>

namespace detexture {
namespace {

// The live folder, for the signal handler: its path and the tile count.
char g_folder[4096] = "";
std::size_t g_tiles = 0;
bool g_owner = false;

// "folder/tile-000123.bin" without allocation.
void tile_name(char* out, std::size_t size, const char* folder, const char* kind, std::size_t t) {
  std::size_t k = 0;
  for (const char* s = folder; *s && k + 1 < size; ++s) out[k++] = *s;
  for (const char* s = "/"; *s && k + 1 < size; ++s) out[k++] = *s;
  for (const char* s = kind; *s && k + 1 < size; ++s) out[k++] = *s;
  char digits[24];
  int d = 0;
  do {
    digits[d++] = static_cast<char>('0' + t % 10);
    t /= 10;
  } while (t > 0 || d < 6);
  if (k + 1 < size) out[k++] = '-';
  while (d > 0 && k + 1 < size) out[k++] = digits[--d];
  for (const char* s = ".bin"; *s && k + 1 < size; ++s) out[k++] = *s;
  out[k] = '\0';
}

void remove_all(const char* folder, std::size_t tiles, bool owner) noexcept {
  char name[4200];
  for (std::size_t t = 0; t < tiles; ++t)
    for (const char* kind : {"tile", "result"}) {
      tile_name(name, sizeof name, folder, kind, t);
      unlink(name);
    }
  if (owner) rmdir(folder);
}

}  // namespace

void remove_tile_bins() noexcept {
  if (g_folder[0] != '\0') remove_all(g_folder, g_tiles, g_owner);
}

TileBins::TileBins(const std::string& parent, std::size_t tiles, bool owner)
    : tiles_(tiles), owner_(owner) {
  if (owner) {
    std::string pattern = parent + "/detexture-XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (!mkdtemp(buffer.data()))
      throw std::runtime_error("cannot create a temporary folder in '" + parent +
                               "' (--temp-dir): " + std::strerror(errno));
    folder_ = buffer.data();
  } else {
    folder_ = parent;
  }
  if (owner && folder_.size() + 64 < sizeof g_folder) {
    std::memcpy(g_folder, folder_.c_str(), folder_.size() + 1);
    g_tiles = tiles;
    g_owner = owner;
  }
}

TileBins::~TileBins() {
  // Only the owner removes: another rank's TileBins ends while rank 0 still
  // reads the result files.
  if (owner_) remove_all(folder_.c_str(), tiles_, owner_);
  g_folder[0] = '\0';
}

std::string TileBins::path(std::size_t tile, const char* kind) const {
  char name[4200];
  tile_name(name, sizeof name, folder_.c_str(), kind, tile);
  return name;
}

void TileBins::bin(PlyVertexReader& reader, const TilePlan& plan, std::vector<std::uint64_t>* core,
                   std::vector<std::uint64_t>* points,
                   const std::function<void(double)>& progress) {
  const PlyVertexLayout& L = reader.layout();
  core->assign(plan.tiles.size(), 0);
  points->assign(plan.tiles.size(), 0);
  std::vector<std::FILE*> files(plan.tiles.size(), nullptr);
  std::size_t open = 0;
  auto close_all = [&files]() {
    for (std::FILE*& f : files)
      if (f) std::fclose(f), f = nullptr;
  };
  try {
    reader.rewind();
    std::vector<unsigned char> block;
    std::vector<std::size_t> of;
    std::uint64_t index = 0;
    while (const std::size_t got = reader.read(1 << 16, &block)) {
      for (std::size_t k = 0; k < got; ++k, ++index) {
        const unsigned char* record = block.data() + k * L.record_size;
        const Eigen::Vector3d p = record_position(L, record, index, "input");
        tiles_of_point(plan, p, &of);
        ++(*core)[core_tile(plan, p)];
        for (const std::size_t t : of) {
          ++(*points)[t];
          if (!files[t]) {
            if (++open > 1000)
              throw std::runtime_error(
                  "more than 1000 tiles hold points; give a larger --tile (or --memory-limit)");
            files[t] = std::fopen(path(t).c_str(), "wb");
            if (!files[t])
              throw std::runtime_error("cannot create '" + path(t) + "': " + std::strerror(errno));
            std::setvbuf(files[t], nullptr, _IOFBF, 1 << 18);
          }
          if (std::fwrite(&index, sizeof index, 1, files[t]) != 1 ||
              std::fwrite(record, L.record_size, 1, files[t]) != 1)
            throw std::runtime_error("cannot write '" + path(t) + "': " + std::strerror(errno) +
                                     " (is --temp-dir full?)");
        }
      }
      if (progress) progress(static_cast<double>(index) / static_cast<double>(L.count));
    }
    for (std::size_t t = 0; t < files.size(); ++t)
      if (files[t]) {
        const bool ok = std::fclose(files[t]) == 0;
        files[t] = nullptr;
        if (!ok)
          throw std::runtime_error("cannot write '" + path(t) + "': " + std::strerror(errno) +
                                   " (is --temp-dir full?)");
      }
  } catch (...) {
    close_all();
    throw;
  }
}

void TileBins::read(std::size_t tile, std::size_t record_size, std::vector<std::uint64_t>* indices,
                    std::vector<unsigned char>* records) const {
  const std::string name = path(tile);
  std::FILE* f = std::fopen(name.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open '" + name + "': " + std::strerror(errno));
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  std::fseek(f, 0, SEEK_SET);
  const std::size_t entry = sizeof(std::uint64_t) + record_size;
  const std::size_t m = size > 0 ? static_cast<std::size_t>(size) / entry : 0;
  indices->resize(m);
  records->resize(m * record_size);
  std::vector<unsigned char> block(entry * 4096);
  std::size_t k = 0;
  while (k < m) {
    const std::size_t want = std::min<std::size_t>(4096, m - k);
    if (std::fread(block.data(), entry, want, f) != want) {
      std::fclose(f);
      throw std::runtime_error("cannot read '" + name + "' (truncated)");
    }
    for (std::size_t j = 0; j < want; ++j, ++k) {
      std::memcpy(&(*indices)[k], block.data() + j * entry, sizeof(std::uint64_t));
      std::memcpy(records->data() + k * record_size, block.data() + j * entry + 8, record_size);
    }
  }
  std::fclose(f);
}

void TileBins::remove(std::size_t tile) const { unlink(path(tile).c_str()); }

}  // namespace detexture
