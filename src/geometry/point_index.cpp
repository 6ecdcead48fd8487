// The one place where nanoflann is used and where a radius is squared.
#include "detexture/geometry/point_index.h"

#include <algorithm>
#include <limits>
#include <nanoflann.hpp>
#include <stdexcept>

namespace detexture {
namespace {

// nanoflann adaptor over the caller's matrix: the index never owns the data.
struct PositionsAdaptor {
  const Positions& P;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(P.rows()); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return P(i, dim); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PositionsAdaptor>,
                                        PositionsAdaptor, 3, std::uint32_t>;

}  // namespace

struct PointIndex::Impl {
  explicit Impl(const Positions& P)
      : adaptor{P}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
  PositionsAdaptor adaptor;
  KdTree tree;
};

PointIndex::PointIndex(const Positions& P) {
  if (static_cast<std::uint64_t>(P.rows()) >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("clouds of more than 2^32-1 points are not supported");
  impl_ = std::make_unique<Impl>(P);
}

PointIndex::~PointIndex() = default;

std::uint32_t PointIndex::nearest(const double q[3], double* distance_sq) const {
  std::uint32_t index = 0;
  double d = 0.0;
  impl_->tree.knnSearch(q, 1, &index, &d);
  if (distance_sq) *distance_sq = d;
  return index;
}

void PointIndex::nearest(const double q[3], std::size_t k, std::vector<std::uint32_t>& index,
                         std::vector<double>& distance_sq) const {
  k = std::min<std::size_t>(k, impl_->adaptor.kdtree_get_point_count());
  index.resize(k);
  distance_sq.resize(k);
  const std::size_t got = impl_->tree.knnSearch(q, k, index.data(), distance_sq.data());
  index.resize(got);
  distance_sq.resize(got);
}

void PointIndex::within(const double q[3], double radius,
                        std::vector<std::pair<std::uint32_t, double>>& found) const {
  const double radius_sq = radius * radius;
  found.clear();
  impl_->tree.radiusSearch(q, radius_sq, found, nanoflann::SearchParams(32, 0.0f, false));
}

}  // namespace detexture
