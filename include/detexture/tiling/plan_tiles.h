// Tile planning for clouds processed piece by piece: the bounding box is cut
// into a grid of cubes (the cores), each widened by a halo. Every point
// belongs to exactly one core; a tile is processed on its core and halo
// points, and only its core's results are kept (run_tile.h).
//
// Pure functions of the bounds, the halo and the budget: the same inputs give
// the same tiles on every rank and every run, which the out-of-core and MPI
// drivers rely on (they bin points to tiles with tiles_of_point).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/types.h"

namespace detexture {

/// An axis-aligned box [lo, hi] (closed).
struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
};

/// The bounding box of P (#P by 3, at least one row).
Box bounding_box(const Positions& P);

struct Tile {
  std::size_t index = 0;          ///< in TilePlan::tiles, x fastest
  Eigen::Vector3i cell{0, 0, 0};  ///< grid cell
  Box core;                       ///< the points this tile owns (see core_tile)
  Box extended;                   ///< core widened by the halo on every side
};

struct TilePlan {
  Box bounds;                     ///< of the whole cloud
  double tile_size = 0.0;         ///< edge of a core cube, in the cloud's units
  double halo = 0.0;              ///< width added on every side, in the cloud's units
  Eigen::Vector3i grid{1, 1, 1};  ///< cells per axis
  std::vector<Tile> tiles;        ///< grid(0) * grid(1) * grid(2) tiles
};

/// Cut `bounds` into cubes of edge `tile_size` (the last cube on an axis may
/// stick out of the bounds), each widened by `halo` (≥ 0). Throws
/// std::invalid_argument for a non-positive or non-finite tile_size, a
/// negative halo, or more than 2^24 tiles (a tile size far too small for
/// the cloud).
TilePlan plan_tiles(const Box& bounds, double tile_size, double halo);

/// The tile whose core holds p: cell floor((p - lo) / tile_size), clamped to
/// the grid, so points on the upper bounds and outside the bounds still get
/// one. Every point has exactly one core tile.
std::size_t core_tile(const TilePlan& plan, const Eigen::Vector3d& p);

/// Append to `out` (cleared first) the tiles whose extended box holds p, in
/// increasing index: always including core_tile(plan, p); at most 8 when the
/// halo is below half the tile size.
void tiles_of_point(const TilePlan& plan, const Eigen::Vector3d& p, std::vector<std::size_t>* out);

/// Counts of a sample of the cloud on a fine grid over `bounds`, from which
/// choose_tile_size estimates how many points each tile would hold.
struct PointHistogram {
  Box bounds;
  int resolution = 64;                ///< cells per axis
  double weight = 1.0;                ///< points each sampled point stands for
  std::vector<std::uint32_t> counts;  ///< resolution³, x fastest
};

/// Histogram of the rows of P (a sample of the cloud, each row standing for
/// `weight` points) over `bounds`.
PointHistogram point_histogram(const Positions& P, const Box& bounds, double weight = 1.0,
                               int resolution = 64);

/// The largest tile size (a power-of-two fraction of the bounds' longest
/// edge) whose every tile, halo included, holds at most `max_points` points
/// by the histogram (an overestimate: cells partly inside a box count
/// whole). Throws ResourceLimitError (estimate_neighborhoods_memory.h) when
/// even tiles of edge 2 × halo would hold more: the halo alone exceeds the
/// budget.
double choose_tile_size(const PointHistogram& histogram, double halo, double max_points);

}  // namespace detexture
