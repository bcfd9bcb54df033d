/// @file cmd_merge.cpp
/// `clothbench merge`: the shards of a sweep (--shard K/N) joined into the unsharded sweep's
/// files.

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"
#include "harness/sweeps/shard.hpp"

namespace clothbench::cli {
namespace {

struct MergeArgs {
  std::string out_dir;
  std::vector<std::string> shard_dirs;
};

int execute_merge(const MergeArgs& a) {
  for (const std::string& d : a.shard_dirs) {
    std::error_code ec;
    if (std::filesystem::equivalent(a.out_dir, d, ec))
      throw UserError("merge: the output folder " + a.out_dir +
                      " is one of the shard folders; choose another");
  }
  const OutputLock lock(a.out_dir);
  const MergeSummary m = merge_shards(a.out_dir, a.shard_dirs);
  std::cout << "merged " << m.shards << " shards of " << (m.command == "accuracy" ? "an " : "a ")
            << m.command << " sweep: " << m.rows << " rows in " << a.out_dir << "/" << m.table
            << "\n";
  if (m.command == "accuracy")
    std::cout << "for the convergence fits and the recommendation, run the sweep's command "
                 "again on the merged folder without --shard: clothbench accuracy SCENARIO "
                 "OPTIONS --resume -o "
              << a.out_dir << " (it keeps every row and runs nothing new)\n";
  return kExitOk;
}

}  // namespace

Command add_merge_command(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* merge = app.add_subcommand(
      "merge",
      "Join the shards of a sweep run with --shard K/N (stability, accuracy, map) into one\n"
      "folder holding the files the unsharded sweep writes, rows in its order. Refuses folders\n"
      "of different sweeps (command, scenario, options, clothbench version), a shard missing or\n"
      "given twice, and a row missing, doubled or in the wrong shard. Example:\n"
      "  clothbench stability -e custom-rk4 --shard 1/2 -o out/s1   (and 2/2 -o out/s2)\n"
      "  clothbench merge out/all out/s1 out/s2");
  merge->add_option("out", a->out_dir, "output folder for the merged sweep")->required();
  merge->add_option("shards", a->shard_dirs, "the shard folders, in any order")->required();
  return {merge, [a] { return execute_merge(*a); }};
}

}  // namespace clothbench::cli
