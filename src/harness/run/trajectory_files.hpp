#pragma once
/// @file trajectory_files.hpp
/// The run's trajectories for the report's player and the exports: every engine's positions
/// every animation_interval, and the colliders' positions, as float32 .npy files that numpy
/// reads in one call, with a JSON index (trajectory/trajectory.json) that says what they hold.

#include <memory>
#include <string>
#include <vector>

#include "harness/io/csv_writer.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

/// Writes dir/trajectory/<engine>.npy (float32, shape frames by #P by 3, particle p = j nu + i,
/// frame k at t = k animation_interval, only frames before a blow-up), colliders.npy (float32,
/// frames by #shapes by 3: each shape's position) and trajectory.json, each into an AtomicFile
/// appended to pending (the caller commits them, the index last). The index also lists the
/// cloth's triangles and, per engine, the trajectory frames where the cloth crosses itself
/// with the triangles involved. Nothing when animation_interval is 0.
void write_trajectories(const RunResult& result, const std::string& dir,
                        std::vector<std::unique_ptr<AtomicFile>>& pending);

/// The bytes of a .npy file (format 1.0) holding a float32 array of the given shape, values
/// in C order (little-endian host).
std::string npy_float32(const std::vector<size_t>& shape, const std::vector<float>& values);

}  // namespace clothbench
