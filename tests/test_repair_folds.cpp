// The fold repair: a vertex pushed across its neighbours is taken back until
// no triangle flips, and moves that fold nothing are kept exactly.
#include "detexture/pipeline/repair_folds.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "detexture/geometry/mesh_folds.h"

namespace detexture {
namespace {

// A flat 7 x 7 grid in z = 0, spacing 1, two triangles per cell.
struct Grid {
  Positions P;
  TriangleIndices T;
};
Grid grid(int side = 7) {
  Grid g;
  g.P.resize(side * side, 3);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) g.P.row(a * side + b) << a, b, 0;
  g.T.resize(2 * (side - 1) * (side - 1), 3);
  int t = 0;
  for (int a = 0; a + 1 < side; ++a)
    for (int b = 0; b + 1 < side; ++b) {
      const int v = a * side + b;
      g.T.row(t++) << v, v + side, v + side + 1;
      g.T.row(t++) << v, v + side + 1, v + 1;
    }
  return g;
}

TEST(RepairFolds, AVertexPushedAcrossItsNeighborsIsTakenBack) {
  const Grid g = grid();
  Positions out = g.P;
  const int centre = 3 * 7 + 3;
  out.row(centre) << 4.6, 3.2, 0.0;  // past its neighbour (4, 3): triangles flip
  out(0, 2) = 0.01;                  // a far corner lifted a little: folds nothing
  ASSERT_GT(measure_folds(out, g.T, g.P).flipped, 0u);
  RepairFoldsReport report;
  const Positions fixed = repair_folds(g.P, out, g.T, {}, &report);
  EXPECT_GT(report.update.flipped, 0u);
  EXPECT_EQ(report.output.flipped, 0u);
  EXPECT_LE(report.output.folded, report.input.folded);
  EXPECT_EQ(fixed(0, 2), 0.01) << "a move that folds nothing is kept exactly";
  // The centre kept some share 2^-k of its move, or none.
  const double kept = (fixed(centre, 0) - 3.0) / 1.6;
  EXPECT_LT(kept, 1.0);
  EXPECT_NEAR((fixed(centre, 1) - 3.0) / 0.2, kept, 1e-12);
  EXPECT_GT(report.vertices_held, 0u);
}

TEST(RepairFolds, DisabledKeepsTheUpdateAndMeasuresIt) {
  const Grid g = grid();
  Positions out = g.P;
  out.row(24) << 4.6, 3.2, 0.0;
  RepairFoldsParams params;
  params.enabled = false;
  RepairFoldsReport report;
  EXPECT_EQ(repair_folds(g.P, out, g.T, params, &report), out);
  EXPECT_EQ(report.output.flipped, report.update.flipped);
  EXPECT_GT(report.output.flipped, 0u);
}

TEST(RepairFolds, NoFoldNoChangeAndBadArgumentsAreRefused) {
  const Grid g = grid();
  Positions out = g.P;
  out.col(2).setConstant(0.5);  // a uniform lift folds nothing
  RepairFoldsReport report;
  EXPECT_EQ(repair_folds(g.P, out, g.T, {}, &report), out);
  EXPECT_EQ(report.rounds, 0);
  RepairFoldsParams bad;
  bad.fold_angle_deg = 180.0;
  EXPECT_THROW(repair_folds(g.P, out, g.T, bad), std::invalid_argument);
  EXPECT_THROW(repair_folds(g.P, Positions(3, 3), g.T), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
