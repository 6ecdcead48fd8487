// Plain data types shared by every stage.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace detexture {

/// #P by 3 row-major list of 3D vectors: positions or unit normals.
using Matrix3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Positions = Matrix3;
using Normals = Matrix3;

/// Progress report from a long stage: a fraction in [0, 1], non-decreasing.
/// Stages call it from one thread at a time, at most about a hundred times.
using ProgressFn = std::function<void(double fraction)>;

/// A number as a user would write it ("2", "0.25", "1e-05"), for messages.
std::string number_text(double value);

/// Length of the bounding-box diagonal of P (0 for fewer than two points).
/// Without overflow or underflow for any extent a double can hold (±1e300,
/// ±1e-300); inf only when the extent itself exceeds the largest double.
double bounding_box_diagonal(const Positions& P);

}  // namespace detexture
