#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/io/csv_writer.hpp"
#include "harness/gate/regression_check.hpp"
#include "harness/io/user_error.hpp"
#include "harness/io/csv_reader.hpp"
#include "harness/sweeps/sweep.hpp"

using clothbench::check_scenario;
using clothbench::CheckOptions;
using clothbench::Gate;
using clothbench::ScratchFolder;
namespace fs = std::filesystem;

namespace {

/// A chain of 6 particles hanging for 0.2 s: a scenario that checks in milliseconds.
std::string chain_scenario(double k, const std::vector<std::string>& integrators) {
  std::ostringstream s;
  s << "name = \"tiny_chain\"\n"
       "duration = 0.2\nframe_interval = 0.01\nsnapshot_interval = 0.1\n"
       "blowup_strain = 1.0\nreference = \"custom-rk4\"\ngravity = [0.0, -9.8, 0.0]\n"
       "[cloth]\nparticles = [1, 6]\nsize = [0.0, 0.5]\ncenter = [0.0, 1.0, 0.0]\n"
       "plane = \"xy\"\nparticle_mass = 0.1\n"
    << "stiffness = { structural = " << k << " }\n"
    << "damping = 1.0\nair_drag = 0.0\n"
       "[[constraint]]\nselect = \"indices\"\nhold = \"xyz\"\nlist = [[0, 5]]\n";
  for (const std::string& i : integrators)
    s << "[[engine]]\nname = \"custom-" << i << "\"\nkind = \"custom\"\nintegrator = \"" << i
      << "\"\ndt = 1e-4\n";
  return s.str();
}

/// Tolerances for the tiny chain: nothing may move (one binary, deterministic runs), and the
/// stability limits of the given integrators, searched on custom-rk4.
std::string chain_tolerances(const std::vector<std::string>& searched) {
  std::string t =
      "final_shape_rms = { abs = 0 }\nstable = { abs = 0 }\nsteps = { abs = 0 }\n"
      "force_evals = { abs = 0 }\ncg_iterations = { abs = 0 }\nmax_energy_error = { abs = 0 }\n"
      "final_rms_vs_reference = { abs = 0 }\nmax_rms_vs_reference = { abs = 0 }\n"
      "final_com_y = { abs = 0 }\ndrape_coefficient = { abs = 0 }\n";
  if (searched.empty()) return t;
  t += "[stability]\nengine = \"custom-rk4\"\nrel_tol = 0.02\nintegrators = [";
  for (size_t i = 0; i < searched.size(); ++i) t += (i ? ", \"" : "\"") + searched[i] + "\"";
  return t + "]\n";
}

/// A 3 x 3 sheet hanging from one top corner for 0.2 s: it swings to one side, so its shape and
/// its mirror image differ.
std::string sheet_scenario() {
  return "name = \"tiny_chain\"\n"
         "duration = 0.2\nframe_interval = 0.01\nsnapshot_interval = 0.1\n"
         "blowup_strain = 1.0\nreference = \"custom-rk4\"\ngravity = [0.0, -9.8, 0.0]\n"
         "[cloth]\nparticles = [3, 3]\nsize = [0.4, 0.4]\ncenter = [0.0, 1.0, 0.0]\n"
         "plane = \"xy\"\nparticle_mass = 0.1\n"
         "stiffness = { structural = 200.0, shear = 200.0, bend = 20.0 }\n"
         "damping = 0.5\nair_drag = 0.0\n"
         "[[constraint]]\nselect = \"indices\"\nhold = \"xyz\"\nlist = [[0, 2]]\n"
         "[[engine]]\nname = \"custom-rk4\"\nkind = \"custom\"\nintegrator = \"rk4\"\n"
         "dt = 1e-4\n"
         "[[engine]]\nname = \"custom-symplectic-euler\"\nkind = \"custom\"\n"
         "integrator = \"symplectic-euler\"\ndt = 1e-4\n";
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
  REQUIRE(out.good());
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A scenario file and a baseline folder of their own.
struct Workspace {
  ScratchFolder folder{"clothbench-test-check-"};
  fs::path root = folder.path();
  fs::path baselines = root / "baselines";
  fs::path chain = baselines / "tiny_chain";

  Workspace() { fs::create_directories(chain); }

  /// Writes a scenario file (engines named custom-<integrator>) and returns its path.
  std::string scenario(const std::string& file, double k,
                       const std::vector<std::string>& integrators) const {
    const fs::path p = root / file;
    write(p, chain_scenario(k, integrators));
    return p.string();
  }
  CheckOptions options() const {
    CheckOptions o;
    o.baseline_dir = baselines.string();
    o.progress = false;
    return o;
  }
  CheckOptions update() const {
    CheckOptions o = options();
    o.update = true;
    return o;
  }
};

/// RMS distance (m) between one engine's final shapes in two shape.csv texts.
double shape_rms(const std::string& a, const std::string& b, const std::string& engine) {
  auto rows = [&](const std::string& text) {
    std::vector<std::vector<double>> r;
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      const auto f = clothbench::split_csv_line(line);
      if (f[0] == engine) r.push_back({std::stod(f[3]), std::stod(f[4]), std::stod(f[5])});
    }
    return r;
  };
  const auto ra = rows(a), rb = rows(b);
  REQUIRE(ra.size() == rb.size());
  double sum = 0.0;
  for (size_t p = 0; p < ra.size(); ++p)
    for (int c = 0; c < 3; ++c) sum += (ra[p][c] - rb[p][c]) * (ra[p][c] - rb[p][c]);
  return std::sqrt(sum / double(ra.size()));
}

std::vector<Gate> failures(const std::vector<Gate>& gates) {
  std::vector<Gate> f;
  for (const Gate& g : gates)
    if (!g.pass) f.push_back(g);
  return f;
}

/// Rewrites the rows of one engine in a shape.csv: f(i, j, x, y, z) gives the new row.
void rewrite_shape(const fs::path& p, const std::string& engine,
                   const std::function<std::vector<double>(const std::vector<double>&)>& f) {
  std::istringstream in(read(p));
  std::string line, out;
  std::getline(in, line);
  out = line + "\n";
  while (std::getline(in, line)) {
    const auto fields = clothbench::split_csv_line(line);
    if (fields[0] != engine) {
      out += line + "\n";
      continue;
    }
    std::vector<double> row;
    for (size_t k = 1; k < fields.size(); ++k) row.push_back(std::stod(fields[k]));
    const std::vector<double> r = f(row);
    out += engine + "," + std::to_string(int(r[0])) + "," + std::to_string(int(r[1]));
    for (int k = 2; k < 5; ++k) out += "," + clothbench::format_double(r[size_t(k)]);
    out += "\n";
  }
  write(p, out);
}

/// The gate of one engine and quantity.
Gate find_gate(const std::vector<Gate>& gates, const std::string& engine,
               const std::string& quantity) {
  for (const Gate& g : gates)
    if (g.engine == engine && g.quantity == quantity) return g;
  FAIL("no gate for " << engine << " " << quantity);
  return Gate{};
}

/// Sets an environment variable for the life of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old, m_had = true;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (m_had)
      ::setenv(m_name, m_old.c_str(), 1);
    else
      ::unsetenv(m_name);
  }

 private:
  const char* m_name;
  std::string m_old;
  bool m_had = false;
};

}  // namespace

TEST_CASE("a scratch folder is a new one every time and goes on every way out", "[regression]") {
  std::string first, second;
  try {
    const ScratchFolder a("clothbench-test-scratch-"), b("clothbench-test-scratch-");
    first = a.path();
    second = b.path();
    CHECK(first != second);
    CHECK(fs::is_directory(first));
    CHECK(fs::is_directory(second));
    write(fs::path(first) / "file", "x");
    throw std::runtime_error("leaving by an exception");
  } catch (const std::runtime_error&) {
  }
  CHECK_FALSE(fs::exists(first));
  CHECK_FALSE(fs::exists(second));
}

TEST_CASE("check searches stability in a folder of its own and leaves none behind",
          "[regression]") {
  // Two checks of one scenario run at once under ctest -j. A fixed folder per scenario was
  // shared and removed by whichever finished first: here a folder under that fixed name stands
  // for the other run's, and must survive.
  const Workspace w;
  const ScratchFolder tmp("clothbench-test-tmpdir-");
  const ScopedEnv env("TMPDIR", tmp.path());
  const fs::path other = fs::path(tmp.path()) / "clothbench-check-tiny_chain";
  fs::create_directories(other);
  write(other / "stability.csv", "another run's table\n");
  write(w.chain / "tolerances.toml", chain_tolerances({"symplectic-euler"}));
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});

  check_scenario(sc, w.update());
  const std::vector<Gate> gates = check_scenario(sc, w.options());
  CHECK(failures(gates).empty());
  CHECK(read(other / "stability.csv") == "another run's table\n");
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(tmp.path())) left.push_back(e.path().string());
  CHECK(left == std::vector<std::string>{other.string()});
}

TEST_CASE("check fails every engine that is on one side only", "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml", chain_tolerances({}));
  check_scenario(w.scenario("recorded.toml", 1000, {"rk4", "symplectic-euler"}), w.update());

  SECTION("recorded in the baseline, not run now") {
    const auto f = failures(check_scenario(w.scenario("fewer.toml", 1000, {"rk4"}), w.options()));
    REQUIRE(f.size() == 1);
    CHECK(f[0].engine == "custom-symplectic-euler");
    CHECK(f[0].quantity == "ran");
    CHECK_THAT(f[0].note, Catch::Contains("did not run"));
  }
  SECTION("run now, without a baseline") {
    const auto f = failures(check_scenario(
        w.scenario("more.toml", 1000, {"rk4", "symplectic-euler", "midpoint"}), w.options()));
    REQUIRE(f.size() == 1);
    CHECK(f[0].engine == "custom-midpoint");
    CHECK(f[0].quantity == "ran");
    CHECK_THAT(f[0].note, Catch::Contains("no baseline"));
  }
}

TEST_CASE("check fails a recorded stability limit it no longer searches", "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml", chain_tolerances({"symplectic-euler", "midpoint"}));
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});
  check_scenario(sc, w.update());
  REQUIRE(failures(check_scenario(sc, w.options())).empty());

  SECTION("an integrator left out of [stability]") {
    write(w.chain / "tolerances.toml", chain_tolerances({"symplectic-euler"}));
    const auto f = failures(check_scenario(sc, w.options()));
    REQUIRE(f.size() == 1);
    CHECK(f[0].engine == "custom-rk4/midpoint");
    CHECK_THAT(f[0].note, Catch::Contains("not searched"));
  }
  SECTION("no [stability] table at all") {
    write(w.chain / "tolerances.toml", chain_tolerances({}));
    const auto f = failures(check_scenario(sc, w.options()));
    REQUIRE(f.size() == 2);
    CHECK_THAT(f[0].note, Catch::Contains("no [stability] table"));
  }
}

TEST_CASE("check --update refuses --set unless a perturbed baseline is asked for", "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml", chain_tolerances({}));
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});
  check_scenario(sc, w.update());
  const std::string recorded = read(w.chain / "metrics.csv");

  CheckOptions o = w.update();
  o.overrides = {"cloth.damping=0"};
  try {
    check_scenario(sc, o);
    FAIL("a perturbed baseline was recorded");
  } catch (const clothbench::UserError& e) {
    CHECK_THAT(e.what(), Catch::Contains("--record-perturbed"));
  }
  CHECK(read(w.chain / "metrics.csv") == recorded);

  o.record_perturbed = true;
  check_scenario(sc, o);
  CHECK(read(w.chain / "metrics.csv") != recorded);
}

TEST_CASE("check --update says how far each shape moved and which stability limits changed",
          "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml", chain_tolerances({"symplectic-euler"}));
  check_scenario(w.scenario("soft.toml", 1000, {"rk4", "symplectic-euler"}), w.update());
  const std::string before = read(w.chain / "shape.csv");
  // four times stiffer springs: a shorter chain, a stability limit about half as large
  const std::vector<Gate> changed =
      check_scenario(w.scenario("stiff.toml", 4000, {"rk4", "symplectic-euler"}), w.update());
  const std::string after = read(w.chain / "shape.csv");
  auto find = [&](const std::string& engine, const std::string& quantity) {
    for (const Gate& g : changed)
      if (g.engine == engine && g.quantity == quantity) return g;
    FAIL("no change reported for " << engine << " " << quantity);
    return Gate{};
  };
  for (const std::string engine : {"custom-rk4", "custom-symplectic-euler"}) {
    const double moved = shape_rms(before, after, engine);
    INFO(engine << " moved " << moved << " m");
    REQUIRE(moved > 0.0);
    CHECK(find(engine, "final_shape_rms").now == Approx(moved).epsilon(1e-12));
  }
  const Gate lo = find("custom-rk4/symplectic-euler", "stable_dt");
  const Gate hi = find("custom-rk4/symplectic-euler", "first_unstable_dt");
  CHECK(lo.now < 0.6 * lo.baseline);
  CHECK(hi.now < 0.6 * hi.baseline);
  CHECK(lo.note == "updated");
}

TEST_CASE("the stability gate wants the recorded bracket, not a neighbouring one", "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml", chain_tolerances({"symplectic-euler"}));
  // stiff enough that the limit is some two hundred steps of the 0.2 s run: the search, which
  // keeps whole step counts, then resolves it to its 2% tolerance
  const std::string sc = w.scenario("tiny_chain.toml", 1e5, {"rk4", "symplectic-euler"});
  check_scenario(sc, w.update());
  const fs::path table = w.chain / "stability.csv";
  const auto rows = [&] {
    std::istringstream in(read(table));
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    return clothbench::split_csv_line(row);
  }();
  const double lo = std::stod(rows[2]), hi = std::stod(rows[3]);
  auto record = [&](double a, double b) {
    write(table, "engine,integrator,stable_dt,first_unstable_dt\ncustom-rk4,symplectic-euler," +
                     clothbench::format_double(a) + "," + clothbench::format_double(b) + "\n");
  };
  // a miss fails both ends of the bracket
  auto stability_failures = [&] {
    int n = 0;
    for (const Gate& g : failures(check_scenario(sc, w.options())))
      n += g.engine == "custom-rk4/symplectic-euler";
    return n;
  };

  SECTION("the bracket above") {
    // within the old rule |stable_dt - recorded| <= rel_tol * recorded, yet the run at hi,
    // recorded unstable, would now be stable
    REQUIRE(hi - lo <= 0.02 * lo);
    record(hi, hi * hi / lo);
    CHECK(stability_failures() == 2);
  }
  SECTION("the bracket below") {
    record(lo * lo / hi, lo);
    CHECK(stability_failures() == 2);
  }
  SECTION("a bracket that overlaps") {
    record(std::sqrt(lo * hi), hi * std::sqrt(hi / lo));
    CHECK(stability_failures() == 0);
  }
}

TEST_CASE("the stability gate lets brackets that share an end pass when told to", "[regression]") {
  // On the flag, the run at one bisection dt turns either way between builds: adjacent = true
  const Workspace w;
  std::string tol = chain_tolerances({"symplectic-euler"});
  tol.insert(tol.find("rel_tol"), "adjacent = true\n");
  write(w.chain / "tolerances.toml", tol);
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});
  check_scenario(sc, w.update());
  const fs::path table = w.chain / "stability.csv";
  std::istringstream in(read(table));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const auto f = clothbench::split_csv_line(row);
  const double lo = std::stod(f[2]), hi = std::stod(f[3]);
  auto failing = [&](double a, double b) {
    write(table, "engine,integrator,stable_dt,first_unstable_dt\ncustom-rk4,symplectic-euler," +
                     clothbench::format_double(a) + "," + clothbench::format_double(b) + "\n");
    return failures(check_scenario(sc, w.options())).size();
  };
  CHECK(failing(hi, hi * hi / lo) == 0);                  // shares hi
  CHECK(failing(lo * lo / hi, lo) == 0);                  // shares lo
  CHECK(failing(hi * 1.001, hi * hi / lo * 1.001) == 2);  // a gap, however small
}

TEST_CASE("check shows an ungated quantity with its reason and still gates the rest",
          "[regression]") {
  const Workspace w;
  write(w.chain / "tolerances.toml",
        chain_tolerances({}) +
            "[ungated.custom-symplectic-euler]\nquantities = [\"final_com_y\"]\n"
            "reason = \"a reason measured for this test\"\n");
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});
  check_scenario(sc, w.update());
  // both engines' final_com_y recorded 1 m off
  std::string metrics = read(w.chain / "metrics.csv"), moved;
  std::istringstream in(metrics);
  std::string line;
  while (std::getline(in, line)) {
    const auto fields = clothbench::split_csv_line(line);
    if (fields.size() == 3 && fields[1] == "final_com_y")
      line = fields[0] + ",final_com_y," + clothbench::format_double(std::stod(fields[2]) + 1.0);
    moved += line + "\n";
  }
  write(w.chain / "metrics.csv", moved);
  const std::vector<Gate> gates = check_scenario(sc, w.options());
  const Gate ungated = find_gate(gates, "custom-symplectic-euler", "final_com_y");
  CHECK(ungated.pass);
  CHECK_FALSE(ungated.gated);
  CHECK_THAT(ungated.note, Catch::Contains("a reason measured for this test"));
  CHECK_FALSE(find_gate(gates, "custom-rk4", "final_com_y").pass);
  CHECK(failures(gates).size() == 1);
}

TEST_CASE("tolerances that name an engine the scenario lacks are refused", "[regression]") {
  const Workspace w;
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4", "symplectic-euler"});
  SECTION("ungated") {
    write(w.chain / "tolerances.toml",
          chain_tolerances({}) +
              "[ungated.custom-midpoint]\nquantities = [\"final_com_y\"]\n"
              "reason = \"no such engine\"\n");
    CHECK_THROWS_WITH(check_scenario(sc, w.update()), Catch::Contains("custom-midpoint"));
  }
  SECTION("mirror") {
    write(w.chain / "tolerances.toml",
          chain_tolerances({}) + "[mirror]\nengines = [\"custom-midpoint\"]\n");
    CHECK_THROWS_WITH(check_scenario(sc, w.update()), Catch::Contains("custom-midpoint"));
  }
}

TEST_CASE("a [mirror] engine's shape passes as the recorded one or its mirror image, no other",
          "[regression]") {
  const Workspace w;
  const fs::path sc = w.root / "sheet.toml";
  write(sc, sheet_scenario());
  const std::string engine = "custom-symplectic-euler";
  write(w.chain / "tolerances.toml", chain_tolerances({}));
  check_scenario(sc.string(), w.update());
  // record the mirror image instead: x -> -x across the cloth's centre plane, i -> 2 - i
  rewrite_shape(w.chain / "shape.csv", engine, [](const std::vector<double>& r) {
    return std::vector<double>{2 - r[0], r[1], -r[2], r[3], r[4]};
  });
  auto shape_gate = [&] {
    return find_gate(check_scenario(sc.string(), w.options()), engine, "final_shape_rms");
  };
  const Gate plain = shape_gate();
  INFO("the sheet's shape is " << plain.now << " m from its mirror image");
  CHECK_FALSE(plain.pass);

  write(w.chain / "tolerances.toml",
        chain_tolerances({}) + "[mirror]\nengines = [\"" + engine + "\"]\n");
  const Gate mirrored = shape_gate();
  CHECK(mirrored.pass);
  CHECK(mirrored.note == "to the mirror image");

  // a shape that is neither: the mirror image 1 mm lower
  rewrite_shape(w.chain / "shape.csv", engine, [](const std::vector<double>& r) {
    return std::vector<double>{r[0], r[1], r[2], r[3] - 1e-3, r[4]};
  });
  CHECK_FALSE(shape_gate().pass);
}

TEST_CASE("a negative or NaN tolerance and an unknown key are refused with file, line and key",
          "[regression]") {
  const Workspace w;
  const std::string sc = w.scenario("tiny_chain.toml", 1000, {"rk4"});
  // chain_tolerances puts final_shape_rms on line 1 and the [stability] keys from line 12
  const std::string file = (w.chain / "tolerances.toml").string();
  const auto refused = [&](const std::string& tolerances, const std::string& message) {
    write(w.chain / "tolerances.toml", tolerances);
    CHECK_THROWS_WITH(check_scenario(sc, w.update()), Catch::Contains(file + message));
  };
  const std::string rest = chain_tolerances({}).substr(chain_tolerances({}).find('\n') + 1);
  refused("final_shape_rms = { abs = -1 }\n" + rest,
          ":1: final_shape_rms.abs: expected a finite number >= 0, got -1");
  refused("final_shape_rms = { abs = nan }\n" + rest,
          ":1: final_shape_rms.abs: expected a finite number >= 0, got nan");
  refused("final_shape_rms = { rel = -inf }\n" + rest,
          ":1: final_shape_rms.rel: expected a finite number >= 0, got -inf");
  refused("final_shape_rms = { abs = 0, absolute = 1 }\n" + rest,
          ":1: final_shape_rms.absolute: unknown key (expected one of abs, rel)");
  refused(chain_tolerances({"symplectic-euler"}) + "rel_tolerance = 0.1\n",
          ":15: stability.rel_tolerance: unknown key");
  refused(chain_tolerances({"symplectic-euler"}) + "[mirror]\nengine = [\"custom-rk4\"]\n",
          ":16: mirror.engine: unknown key (expected one of engines)");
}
