#pragma once
/// @file types.hpp
/// The matrix layout every part of clothbench uses.
///
/// Particle p of a grid with nu by nv particles sits at column p = j * nu + i, where i runs
/// along the grid's u direction and j along v. Per-particle vectors (positions, velocities,
/// forces) are 3 by #P matrices stored row-major, so each coordinate is one contiguous row
/// (structure of arrays): the force kernels stream x, y and z separately and vectorise.

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace cloth {

/// 3 by #P matrix, one column per particle, each coordinate row contiguous in memory.
using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;
/// #P vector, one entry per particle.
using VectorX = Eigen::VectorXd;
using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;

/// A triangle of the cloth's surface: three particle indices (columns of a 3 by #P matrix).
using Triangle = std::array<int, 3>;

/// Bit mask of held axes for one particle.
enum AxisBits : std::uint8_t { kHoldX = 1, kHoldY = 2, kHoldZ = 4, kHoldAll = 7 };

}  // namespace cloth
