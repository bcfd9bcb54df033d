/// @file shard.cpp

#include "harness/sweeps/shard.hpp"

#include <toml++/toml.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "harness/io/csv_reader.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/build_info.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

const char* const kShardFile = "shard.toml";

namespace {

constexpr int kMaxShards = 100000;

/// One shard folder as read back for a merge.
struct ShardFolder {
  std::string dir;  // as given
  Shard shard;
  ShardPlan plan;
  std::string version, git_commit;
  std::vector<std::string> sidecar_texts;  // as plan.sidecars
};

std::string toml_list(const std::vector<std::string>& items) {
  std::string t;
  for (size_t i = 0; i < items.size(); ++i) t += (i ? ", " : "") + toml_string(items[i]);
  return t;
}

std::vector<std::string> string_list(const toml::table& t, const char* key) {
  std::vector<std::string> items;
  if (const toml::array* a = t[key].as_array())
    for (const toml::node& n : *a) items.push_back(n.value_or(std::string()));
  return items;
}

std::string shard_text(const Shard& s, const ShardPlan& p) {
  std::string t = "# shard " + s.text() + " of a clothbench " + p.command +
                  " sweep; `clothbench merge OUT DIR...` joins the shards\n" +
                  "command = " + toml_string(p.command) + "\nshard = " + std::to_string(s.index) +
                  "\nshards = " + std::to_string(s.count) + "\nversion = " + toml_string(kVersion) +
                  "\ngit_commit = " + toml_string(kGitCommit) +
                  "\ntable = " + toml_string(p.table) + "\nsidecars = [" + toml_list(p.sidecars) +
                  "]\nunit_columns = " + std::to_string(p.unit_columns) +
                  "\nkey_columns = " + std::to_string(p.key_columns) + "\nunits = [\n";
  for (const std::string& u : p.units) t += "  " + toml_string(u) + ",\n";
  return t + "]\n";
}

std::string need_string(const toml::table& t, const char* key, const std::string& path) {
  if (const auto v = t[key].value<std::string>()) return *v;
  throw UserError(path + ": no " + key + " (not a shard file written by clothbench)");
}

int need_int(const toml::table& t, const char* key, const std::string& path) {
  if (const auto v = t[key].value<int64_t>(); v && *v >= 0 && *v <= kMaxShards) return int(*v);
  throw UserError(path + ": " + key + " is missing or not a whole number");
}

/// Reads dir/shard.toml and the sidecar beside it.
ShardFolder read_shard_folder(const std::string& dir) {
  ShardFolder f;
  f.dir = dir;
  const std::string path = dir + "/" + kShardFile;
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) throw UserError(dir + ": no such folder");
  if (!std::filesystem::is_directory(dir, ec))
    throw UserError(dir + ": a file, not the folder of a sharded sweep");
  if (!std::filesystem::exists(path))
    throw UserError(dir + ": no " + kShardFile +
                    ": not the folder of a sharded sweep (stability, accuracy or map with "
                    "--shard K/N)");
  toml::table t;
  try {
    t = toml::parse(read_existing_text(path), path);
  } catch (const toml::parse_error& e) {
    throw UserError(path + ": " + std::string(e.description()));
  }
  f.plan = {need_string(t, "command", path),  need_string(t, "table", path),
            string_list(t, "sidecars"),       need_int(t, "unit_columns", path),
            need_int(t, "key_columns", path), string_list(t, "units")};
  f.shard = {need_int(t, "shard", path), need_int(t, "shards", path)};
  f.version = need_string(t, "version", path);
  f.git_commit = need_string(t, "git_commit", path);
  if (f.shard.index < 1 || f.shard.index > f.shard.count)
    throw UserError(path + ": shard " + f.shard.text() + " is not a shard K/N with 1 <= K <= N");
  for (const std::string& s : f.plan.sidecars)
    f.sidecar_texts.push_back(read_existing_text(dir + "/" + s));
  return f;
}

/// Throws UserError unless b belongs to the same sweep as a.
void require_same_sweep(const ShardFolder& a, const ShardFolder& b) {
  const auto differ = [&](const std::string& what, const std::string& x, const std::string& y) {
    throw UserError("cannot merge " + a.dir + " and " + b.dir + ": they are shards of different " +
                    "sweeps (" + what + ": " + x + " and " + y + ")");
  };
  if (a.plan.command != b.plan.command) differ("command", a.plan.command, b.plan.command);
  if (a.shard.count != b.shard.count) differ("shard count", a.shard.text(), b.shard.text());
  if (a.version != b.version || a.git_commit != b.git_commit)
    differ("clothbench version", a.version + " " + a.git_commit, b.version + " " + b.git_commit);
  for (size_t i = 0; i < a.sidecar_texts.size() && i < b.sidecar_texts.size(); ++i)
    if (a.sidecar_texts[i] != b.sidecar_texts[i])
      differ(a.plan.sidecars[i], "another scenario, --set, --vary, option or reference",
             "this one");
  if (a.plan.units != b.plan.units || a.plan.sidecars != b.plan.sidecars ||
      a.plan.table != b.plan.table || a.plan.unit_columns != b.plan.unit_columns ||
      a.plan.key_columns != b.plan.key_columns)
    differ("the sweep's rows", "other engines, integrators or values", "these");
}

/// The folders sorted by shard index; refuses a shard given twice and a missing one.
std::vector<ShardFolder> order_shards(std::vector<ShardFolder> folders) {
  std::vector<const ShardFolder*> by_index(size_t(folders.front().shard.count) + 1, nullptr);
  for (const ShardFolder& f : folders) {
    require_same_sweep(folders.front(), f);
    const ShardFolder*& slot = by_index[size_t(f.shard.index)];
    if (slot)
      throw UserError("cannot merge: " + slot->dir + " and " + f.dir + " are both shard " +
                      f.shard.text());
    slot = &f;
  }
  std::vector<ShardFolder> sorted;
  for (int k = 1; k <= folders.front().shard.count; ++k) {
    if (!by_index[size_t(k)])
      throw UserError("cannot merge: shard " + std::to_string(k) + "/" +
                      std::to_string(folders.front().shard.count) +
                      " is missing (give the folders of all the sweep's shards)");
    sorted.push_back(*by_index[size_t(k)]);
  }
  return sorted;
}

/// Where a row was read, for messages.
std::string where(const CsvRecord& r, const std::string& path) {
  return path + ":" + std::to_string(r.line());
}

/// A merged row: its fields and where it came from.
struct MergedRow {
  std::vector<std::string> fields;
  std::string from;  // PATH:LINE
};

/// Reads every shard's table into rows by unit, refusing rows of the wrong shard, doubled
/// rows, and a header that differs from the first shard's.
std::vector<std::vector<MergedRow>> collect_rows(const std::vector<ShardFolder>& shards,
                                                 std::vector<std::string>& header) {
  const ShardPlan& plan = shards.front().plan;
  std::map<std::string, size_t> unit_index;
  for (size_t i = 0; i < plan.units.size(); ++i) unit_index[plan.units[i]] = i;
  std::vector<std::vector<MergedRow>> by_unit(plan.units.size());
  std::map<std::string, std::string> seen;  // row key -> where
  for (const ShardFolder& f : shards) {
    const std::string path = f.dir + "/" + plan.table;
    if (!std::filesystem::exists(path))
      throw UserError(f.dir + ": no " + plan.table + ": shard " + f.shard.text() +
                      " has not finished (rerun it with --resume)");
    const CsvTable t = read_csv_leniently(path);
    if (header.empty()) header = t.header;
    if (t.header != header)
      throw UserError(path + ": its header differs from " + shards.front().dir + "/" + plan.table);
    for (const CsvRecord& r : t.records) {
      if (r.size() != header.size())
        throw UserError(where(r, path) + ": " + std::to_string(r.size()) + " fields, expected " +
                        std::to_string(header.size()));
      const std::string unit = join_fields(r.fields(), size_t(plan.unit_columns));
      const auto u = unit_index.find(unit);
      if (u == unit_index.end())
        throw UserError(where(r, path) + ": a row for " + unit + ", which the sweep does not have");
      if (!f.shard.owns(u->second))
        throw UserError(where(r, path) + ": a row for " + unit + ", which belongs to shard " +
                        std::to_string(u->second % size_t(f.shard.count) + 1) + "/" +
                        std::to_string(f.shard.count) + ", not to this shard " + f.shard.text());
      const std::string key = join_fields(r.fields(), size_t(plan.key_columns));
      if (const auto s = seen.find(key); s != seen.end())
        throw UserError(where(r, path) + ": a second row for " + key + " (the first is " +
                        s->second + ")");
      seen[key] = where(r, path);
      by_unit[u->second].push_back({r.fields(), where(r, path)});
    }
  }
  return by_unit;
}

/// Throws UserError naming the first unit without a row and the shard that owes it.
void require_every_unit(const std::vector<ShardFolder>& shards,
                        const std::vector<std::vector<MergedRow>>& by_unit) {
  size_t missing = 0, first = 0;
  for (size_t i = by_unit.size(); i-- > 0;)
    if (by_unit[i].empty()) ++missing, first = i;
  if (missing == 0) return;
  const ShardFolder& owner = shards[first % shards.size()];
  throw UserError("cannot merge: " + std::to_string(missing) + " of " +
                  std::to_string(by_unit.size()) + " rows are missing, the first " +
                  shards.front().plan.units[first] + " of shard " + owner.shard.text() + " (" +
                  owner.dir + "/" + owner.plan.table +
                  "): rerun that shard with --resume to finish it");
}

/// Refuses an output folder that holds results this merge would not replace (another
/// command's tables and records, an earlier map's points/, a shard's record) and clears the growing
/// modes an earlier merge left there, so that the folder then holds this merge alone.
void prepare_merge_folder(const std::string& out_dir, const ShardPlan& plan) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(out_dir, ec)) return;
  std::set<std::string> own(plan.sidecars.begin(), plan.sidecars.end());
  own.insert({plan.table, "run.json", "stability_modes", ".clothbench.lock"});
  // results are tables, records and a map's points; other folders (logs, the shards
  // themselves, as scripts/slurm-sweep lays them out) may stay
  const std::set<std::string> results = {".csv", ".toml", ".json", ".npy", ".html"};
  for (const auto& e : fs::directory_iterator(out_dir)) {
    const std::string name = e.path().filename().string();
    const bool result =
        e.is_directory() ? name == "points" : results.count(e.path().extension().string()) > 0;
    if (result && own.count(name) == 0)
      throw UserError("merge: the output folder " + out_dir + " holds " + name +
                      (e.is_directory() ? "/" : "") + ", which a merged " + plan.command +
                      " sweep would not replace (another command's results); choose a new or "
                      "empty folder");
  }
  fs::remove_all(fs::path(out_dir) / "stability_modes", ec);
  if (ec) throw UserError(out_dir + "/stability_modes: cannot clear it: " + ec.message());
}

}  // namespace

/// A stability sweep's growing modes (stability_modes/ROW.npy, ROW the row's index in the
/// whole sweep, so no two shards write the same name; rest.npy the same in each) copied into
/// the merged folder.
void copy_modes(const std::vector<ShardFolder>& shards, const std::string& out_dir) {
  namespace fs = std::filesystem;
  for (const ShardFolder& s : shards) {
    const fs::path modes = fs::path(s.dir) / "stability_modes";
    if (!fs::is_directory(modes)) continue;
    const fs::path to = fs::path(out_dir) / "stability_modes";
    std::error_code ec;
    fs::create_directories(to, ec);
    for (const auto& e : fs::directory_iterator(modes)) {
      if (!ec && e.is_regular_file() && e.path().extension() == ".npy")
        fs::copy_file(e.path(), to / e.path().filename(), fs::copy_options::overwrite_existing, ec);
      if (ec) throw UserError(to.string() + ": cannot copy the growing modes: " + ec.message());
    }
  }
}

MergeSummary merge_shards(const std::string& out_dir, const std::vector<std::string>& dirs) {
  // which sweep: every folder a shard of the same one, every shard there once
  if (dirs.empty()) throw UserError("merge: no shard folders given");
  std::vector<ShardFolder> folders;
  for (const std::string& d : dirs) folders.push_back(read_shard_folder(d));
  const std::vector<ShardFolder> shards = order_shards(folders);
  const ShardPlan& plan = shards.front().plan;

  // the rows: each in its own shard, none twice, none missing
  std::vector<std::string> header;
  const auto by_unit = collect_rows(shards, header);
  require_every_unit(shards, by_unit);

  // the files of the unsharded sweep: the table in its order, the sidecar, run.json
  prepare_merge_folder(out_dir, plan);
  make_directories(out_dir);
  CsvWriter table(out_dir + "/" + plan.table, header);
  size_t rows = 0;
  for (const auto& unit : by_unit)
    for (const MergedRow& r : unit) {
      for (const std::string& field : r.fields) table.add(field);
      table.end_row();
      ++rows;
    }
  std::vector<std::unique_ptr<AtomicFile>> sidecars;
  for (size_t i = 0; i < plan.sidecars.size(); ++i) {
    sidecars.push_back(std::make_unique<AtomicFile>(out_dir + "/" + plan.sidecars[i]));
    sidecars.back()->write(shards.front().sidecar_texts[i]);
  }
  table.commit();
  for (auto& s : sidecars) s->commit();
  copy_modes(shards, out_dir);
  write_run_info(out_dir + "/");
  return {plan.command, plan.table, int(shards.size()), rows};
}

std::string Shard::text() const {
  return std::to_string(index) + "/" + std::to_string(count);
}

Shard parse_shard(const std::string& text) {
  const size_t slash = text.find('/');
  const auto whole = [](const std::string& s) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
      return -1;
    return std::atoi(s.c_str());
  };
  const int k = slash == std::string::npos ? -1 : whole(text.substr(0, slash));
  const int n = slash == std::string::npos ? -1 : whole(text.substr(slash + 1));
  if (k < 1 || n < 1 || k > n || n > kMaxShards)
    throw UserError("--shard " + text + ": expected K/N, shard K of N with 1 <= K <= N <= " +
                    std::to_string(kMaxShards) + " (e.g. --shard 2/8)");
  return {k, n};
}

std::string join_fields(const std::vector<std::string>& fields, size_t count) {
  std::string s;
  for (size_t i = 0; i < count && i < fields.size(); ++i)
    s += (i ? "," : "") + csv_field(fields[i]);
  return s;
}

void record_shard(const std::string& dir, const Shard& s, const ShardPlan& p, bool resume) {
  const std::string path = dir + kShardFile, earlier = read_text(path);
  const std::string now = s.sharded() ? shard_text(s, p) : std::string();
  // a shard of another command's sweep is that command's to finish or merge
  if (!earlier.empty()) {
    toml::table t;
    try {
      t = toml::parse(earlier, path);
    } catch (const toml::parse_error&) {
    }
    const std::string command = t["command"].value_or(std::string());
    if (command != p.command)
      throw UserError(path + ": the folder holds a shard of " +
                      (command.empty() ? std::string("another sweep") : "a " + command + " sweep") +
                      "; a " + p.command +
                      " sweep would mix its results with it; choose another output folder");
  }
  // a folder with no sweep yet resumes as a fresh start, whatever its shard
  const bool fresh = earlier.empty() && !std::filesystem::exists(dir + p.table);
  if (resume && earlier != now && !fresh)
    throw UserError(path + ": cannot resume: the folder holds " +
                    (earlier.empty() ? std::string("an unsharded sweep") : "another shard") +
                    (s.sharded() ? ", not shard " + s.text() + " of this sweep"
                                 : ", and --shard was not given") +
                    "; run without --resume or choose another output folder");
  if (!s.sharded()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    return;
  }
  AtomicFile f(path);
  f.write(now);
  f.commit();
}

}  // namespace clothbench
