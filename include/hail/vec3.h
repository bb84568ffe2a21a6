#pragma once
// Scalar 3-vectors for the API and set-up code. Hot loops use SoA spans instead.

#include <Eigen/Core>

namespace hail {

/// A 3-vector in metres (or m/s, rad/s, ...). Eigen's fixed-size float vector: 12 bytes,
/// no alignment requirement, so it is safe in std::vector and by value.
using Vec3 = Eigen::Vector3f;

}  // namespace hail
