#pragma once
/// @file run_parallel.hpp
/// Independent runs of a sweep spread over threads.

#include <functional>

namespace clothbench {

/// Number of jobs when the user gives none: every core.
int default_jobs();

/// Runs work(i) for every i in [0, n) on up to jobs threads. An exception in any job stops
/// the remaining ones and is rethrown (the first one) after all threads finish.
void run_parallel(int n, int jobs, const std::function<void(int)>& work);

}  // namespace clothbench
