// The exact view-factor method side by side with View3D 4.0 (built from
// ../shared/peers/view3d/build.sh; only run, never linked or copied) on the scenes of
// issue 16: the 5 × 3 × 2.5 m room unmeshed and with its faces split 8/16/32, and unit
// squares 1 m apart with a centred 0.5 m blocker. Both on one thread; View3D timed as a
// whole process (it reads and writes files), radnet as the call. Errors against Howell's
// closed forms (room) and the blocker case's converged value.
//   bench_exact_view_factors OUT.md OUT.csv [VIEW3D]
#include "bench/bench_support.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/primitives.hpp"
#include "geometry/rays/view_factors.hpp"
#include "tests/howell.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>

using namespace radnet::geometry;
using radnet::bench::peakMiB;
using radnet::bench::since;
namespace howell = radnet::howell;
namespace fs = std::filesystem;

namespace {

struct Rect {
  Vec3 origin, u, v;  // front side u × v
  std::string name;
  bool node = true;        // false: an obstruction
  bool two_sided = false;  // the back side is a node too ("<name>b")
};

const double kLx = 5.0, kLy = 3.0, kLz = 2.5;

std::vector<Rect> roomFaces() {
  return {{Vec3(0, 0, kLz), Vec3(0, kLy, 0), Vec3(kLx, 0, 0), "ceiling"},
          {Vec3(0, 0, 0), Vec3(0, kLy, 0), Vec3(0, 0, kLz), "end1"},
          {Vec3(kLx, 0, 0), Vec3(0, 0, kLz), Vec3(0, kLy, 0), "end2"},
          {Vec3(0, 0, 0), Vec3(0, 0, kLz), Vec3(kLx, 0, 0), "side1"},
          {Vec3(0, kLy, 0), Vec3(kLx, 0, 0), Vec3(0, 0, kLz), "side2"},
          {Vec3(0, 0, 0), Vec3(kLx, 0, 0), Vec3(0, kLy, 0), "floor"}};
}

std::vector<Rect> blockedSquares() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), "a"},
          {Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0), "b"},
          {Vec3(0.25, 0.25, 0.5), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0), "shade", false}};
}

// The room's node factors from Howell C-11 (opposite faces) and C-14 (adjacent ones).
Eigen::MatrixXd roomReference() {
  const std::vector<Rect> faces = roomFaces();
  const Vec3 size(kLx, kLy, kLz);
  auto axis = [](const Rect& r) {
    int k = 0;
    r.u.cross(r.v).cwiseAbs().maxCoeff(&k);
    return k;
  };
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      if (i == j) continue;
      const int a = axis(faces[size_t(i)]), b = axis(faces[size_t(j)]);
      if (a == b) {
        const int p = (a + 1) % 3, q = (a + 2) % 3;
        f(i, j) = howell::parallelRectangles(size[p], size[q], size[a]);
      } else {
        const int c = 3 - a - b;
        f(i, j) = howell::perpendicularRectangles(size[c], size[b], size[a]);
      }
    }
  return f;
}

Scene sceneOf(const std::vector<Rect>& rects, int sub) {
  Scene s;
  for (const Rect& r : rects)
    s.addSurface(r.name, r.name, rectangle(r.origin, r.u, r.v, r.node ? sub : 1, r.node ? sub : 1),
                 r.node ? r.name : "", r.two_sided ? r.name + "b" : "");
  return s;
}

// View3D input: every face split sub × sub, the elements combined into the face's first.
void writeVs3(const fs::path& path, const std::vector<Rect>& rects, int sub, double eps) {
  std::ofstream out(path);
  out << std::setprecision(17) << "T radnet bench\nF 3\nC eps=" << eps << " encl=0 list=0 out=0\n";
  std::ostringstream surfaces;
  int vertex = 0, surface = 0;
  for (const Rect& r : rects) {
    const int n = r.node ? sub : 1;
    int first = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        std::array<int, 4> ids{};
        const std::array<std::array<int, 2>, 4> corners = {{{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}}};
        for (size_t k = 0; k < 4; ++k) {
          const Vec3 p = r.origin + r.u * double(corners[k][0]) / n + r.v * double(corners[k][1]) / n;
          out << "V " << ++vertex << " " << p.x() << " " << p.y() << " " << p.z() << "\n";
          ids[k] = vertex;
        }
        ++surface;
        surfaces << (r.node ? "S " : "O ") << surface << " " << ids[0] << " " << ids[1] << " " << ids[2] << " "
                 << ids[3] << " 0 " << (r.node ? first : 0) << " " << (r.node ? 0.999 : 0.0) << " " << r.name << "\n";
        if (first == 0 && r.node) first = surface;
        if (r.two_sided)  // the back: the same corners the other way round (single cells only)
          surfaces << "S " << ++surface << " " << ids[3] << " " << ids[2] << " " << ids[1] << " " << ids[0]
                   << " 0 0 0.999 " << r.name << "b\n";
      }
  }
  out << surfaces.str() << "End of data\n";
}

// Runs View3D; returns the node-factor matrix (rows of the combined surfaces) and seconds.
bool runView3d(const std::string& exe, const fs::path& dir, const std::vector<Rect>& rects, int sub, double eps,
               int nodes, Eigen::MatrixXd& f, double& seconds) {
  const fs::path in = dir / "case.vs3", out = dir / "case.out";
  writeVs3(in, rects, sub, eps);
  const std::string cmd = "cd '" + dir.string() + "' && '" + exe + "' case.vs3 case.out > view3d.txt 2>&1";
  const auto t0 = std::chrono::steady_clock::now();
  if (std::system(cmd.c_str()) != 0) return false;
  seconds = since(t0);
  std::ifstream res(out);
  std::string line;
  std::getline(res, line);  // header
  std::getline(res, line);  // areas
  std::vector<std::vector<double>> rows;
  while (std::getline(res, line)) {
    std::istringstream ss(line);
    std::vector<double> row;
    for (double x; ss >> x;) row.push_back(x);
    rows.push_back(row);
  }
  // Combined surfaces: the matrix is over the surfaces that are not combined into another.
  f = Eigen::MatrixXd::Zero(nodes, nodes);
  for (int i = 0; i < nodes && size_t(i) < rows.size(); ++i)
    for (int j = 0; j < nodes && size_t(j) < rows[size_t(i)].size(); ++j) f(i, j) = rows[size_t(i)][size_t(j)];
  return true;
}

// The 1,600-node satellite of issue 12 scaled: four 1 m bus faces of m × m cells and two
// 3 × 1 m wings of m × 3m cells, front and back, every cell a node.
std::vector<Rect> cellSatellite(int m) {
  std::vector<Rect> rects;
  auto cells = [&](const std::string& name, Vec3 o, Vec3 u, Vec3 v, int nu, int nv, bool two) {
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j)
        rects.push_back({o + u * (double(i) / nu) + v * (double(j) / nv), u / nu, v / nv,
                         name + std::to_string(i) + "_" + std::to_string(j), true, two});
  };
  cells("px", Vec3(0.5, -0.5, -0.5), Vec3(0, 1, 0), Vec3(0, 0, 1), m, m, false);
  cells("mx", Vec3(-0.5, -0.5, -0.5), Vec3(0, 0, 1), Vec3(0, 1, 0), m, m, false);
  cells("py", Vec3(-0.5, 0.5, -0.5), Vec3(0, 0, 1), Vec3(1, 0, 0), m, m, false);
  cells("my", Vec3(-0.5, -0.5, -0.5), Vec3(1, 0, 0), Vec3(0, 0, 1), m, m, false);
  cells("wp", Vec3(0.55, -0.5, 0.0), Vec3(0, 1, 0), Vec3(3, 0, 0), m, 3 * m, true);
  cells("wm", Vec3(-3.55, -0.5, 0.0), Vec3(3, 0, 0), Vec3(0, 1, 0), 3 * m, m, true);
  return rects;
}

// Curved and occluded: a facetted can (wall outside and inside, open top) on a plate, a
// lid disc above it facing down, and a side panel facing the can.
Scene canScene() {
  Scene s;
  s.addSurface("plate", "plate", rectangle(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), "plate", "");
  s.addSurface("can", "can", cylinder(Vec3(0, 0, 0), Vec3(0, 0, 0.6), 0.3, {}, 2, 16), "can", "can.inside");
  s.addSurface("lid", "lid", disc(Vec3(0, 0, 1.0), Vec3(0, 0, -1), 0.5, 0.0, {}, 1, 16), "lid", "");
  s.addSurface("panel", "panel", rectangle(Vec3(1.2, -0.6, 0.1), Vec3(0, 1.2, 0), Vec3(0, 0, 0.8), 1, 1), "", "panel");
  return s;
}

// Error estimates at loose tolerances against the converged answer, and the converged
// answer against 10⁷ rays per node.
std::string coverageSection() {
  const Scene s = canScene();
  std::ostringstream md;
  md << "\n## Error estimates: a curved, occluded scene\n\n"
     << "A facetted can (16 sides; outside and inside nodes) on a plate, a lid above, a side panel.\n"
     << "Covered: entries with |F − F_converged| ≤ the estimate; F_converged at tolerance 1e-10.\n\n"
     << "| tolerance | time (s) | max error | max estimate | covered |\n|---|---|---|---|---|\n";
  const ExactResult ref = exactViewFactors(s, ExactOptions::withTolerance(1e-10));
  const Eigen::MatrixXd fr(ref.view_factors);
  for (double tol : {1e-2, 1e-3, 1e-4, 1e-6}) {
    const auto t0 = std::chrono::steady_clock::now();
    const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(tol));
    const double dt = since(t0);
    const Eigen::MatrixXd f(r.view_factors), e(r.standard_error);
    int covered = 0, total = 0;
    for (Eigen::Index i = 0; i < f.rows(); ++i)
      for (Eigen::Index j = 0; j < f.cols(); ++j) {
        if (fr(i, j) == 0 && f(i, j) == 0) continue;
        ++total;
        covered += std::abs(f(i, j) - fr(i, j)) <= e(i, j) + 1e-15;
      }
    md << "| " << tol << " | " << std::setprecision(3) << dt << " | " << std::scientific << std::setprecision(2)
       << (f - fr).cwiseAbs().maxCoeff() << " | " << e.maxCoeff() << std::defaultfloat << " | " << covered << "/"
       << total << " |\n";
  }
  const RayCaster caster(s);
  ViewFactorOptions mo;
  mo.rays_per_node = 10000000;
  const ViewFactorResult mc = computeViewFactors(caster, mo);
  const Eigen::MatrixXd fm = mc.denseViewFactors(), sm = mc.denseStandardError();
  int inside = 0, total = 0;
  double worst = 0;
  for (Eigen::Index i = 0; i < fm.rows(); ++i)
    for (Eigen::Index j = 0; j < fm.cols(); ++j) {
      if (fr(i, j) == 0 && fm(i, j) == 0) continue;
      ++total;
      const double z = std::abs(fm(i, j) - fr(i, j)) / std::max(sm(i, j), 1e-300);
      inside += z <= 3.29;
      worst = std::max(worst, z);
    }
  md << "\nThe converged answer against 10⁷ rays per node (" << std::setprecision(3) << mc.seconds << " s): " << inside
     << " of " << total << " entries within 3.29 σ, the worst at " << worst << " σ; largest difference "
     << std::scientific << std::setprecision(2) << (fm - fr).cwiseAbs().maxCoeff() << std::defaultfloat << ".\n";
  return md.str();
}

struct Row {
  std::string scene, tool, setting;
  double seconds, error;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string md_path = argc > 1 ? argv[1] : "docs/exact-view-factor-benchmark.md";
  const std::string csv_path = argc > 2 ? argv[2] : "docs/exact-view-factor-benchmark.csv";
  const std::string view3d = argc > 3 ? argv[3] : "";
  const fs::path dir = fs::temp_directory_path() / ("radnet-v3d-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<Row> rows;
  const Eigen::MatrixXd room_ref = roomReference();
  // The blocked squares' reference: the exact method converged (tolerance 1e-11 and 1e-12
  // agree to 1e-12; View3D gives 0.0995063 to its 7 digits).
  const double blocked_ref =
      exactViewFactors(sceneOf(blockedSquares(), 1), ExactOptions::withTolerance(1e-12)).view_factors.coeff(0, 1);
  // Both tools on one scene: radnet at each tolerance, View3D at each eps.
  auto measure = [&](const std::string& name, const std::vector<Rect>& rects, int sub, int nodes,
                     const std::vector<double>& tolerances, const std::function<double(const Eigen::MatrixXd&)>& error) {
    const Scene s = sceneOf(rects, sub);
    for (double tol : tolerances) {
      ExactOptions opt = ExactOptions::withTolerance(tol);
      opt.threads = 1;
      const auto t0 = std::chrono::steady_clock::now();
      const ExactResult r = exactViewFactors(s, opt);
      const double dt = since(t0);
      std::ostringstream set;
      set << "tolerance " << tol;
      rows.push_back({name, "radnet exact", set.str(), dt, error(Eigen::MatrixXd(r.view_factors))});
    }
    if (view3d.empty()) return;
    for (double eps : {1e-4, 1e-6}) {
      Eigen::MatrixXd f;
      double dt = 0;
      if (!runView3d(view3d, dir, rects, sub, eps, nodes, f, dt)) continue;
      std::ostringstream set;
      set << "eps " << eps;
      rows.push_back({name, "View3D 4.0", set.str(), dt, error(f)});
    }
  };
  for (int sub : {1, 8, 16, 32})
    measure("room " + std::to_string(sub) + "×" + std::to_string(sub), roomFaces(), sub, 6, {1e-4, 1e-6, 1e-9},
            [&](const Eigen::MatrixXd& f) { return (f - room_ref).cwiseAbs().maxCoeff(); });
  measure("blocked squares", blockedSquares(), 1, 2, {1e-4, 1e-6, 1e-8},
          [&](const Eigen::MatrixXd& f) { return std::abs(f(0, 1) - blocked_ref); });
  // Satellites: the exact method (every pair) against rays at 4,000 per node; the error of
  // the rays is measured against the exact answer, the exact one is its own estimate.
  std::ostringstream sat;
  sat << "\n## Cell satellites: exact against rays (2 threads)\n\n"
      << "Bus faces and wings as in issue 12 (no dish), every cell a node. Error of the rays:\n"
      << "max |F_rays − F_exact|, and the share of entries of at least 20 expected hits within 3.29 σ\n"
      << "of the exact value (on a 144-node version at 2 M rays per node: 656 of 658); of the\n"
      << "exact method: its largest error estimate.\n\n"
      << "| nodes | method | time (s) | max error | peak memory so far (MiB) |\n|---|---|---|---|---|\n";
  for (int m : {10, 20}) {
    const Scene s = sceneOf(cellSatellite(m), 1);
    const auto t0 = std::chrono::steady_clock::now();
    const ExactResult ex = exactViewFactors(s, ExactOptions::withTolerance(1e-4));
    const double t_exact = since(t0);
    ExactOptions one = ExactOptions::withTolerance(1e-4);
    one.threads = 1;
    const auto t1 = std::chrono::steady_clock::now();
    exactViewFactors(s, one);
    sat << "| " << s.nodes().size() << " | exact, tolerance 1e-4, one thread | " << std::setprecision(3) << since(t1)
        << " | (as above) | – |\n";
    const RayCaster caster(s);
    ViewFactorOptions mo;
    mo.rays_per_node = 4000;
    const ViewFactorResult mc = computeViewFactors(caster, mo);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> diff = mc.view_factors - ex.view_factors;
    std::int64_t inside = 0, total = 0;
    for (Eigen::Index i = 0; i < diff.outerSize(); ++i)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(diff, i); it; ++it) {
        // Entries of fewer than ~20 expected hits have no usable σ from 32 replicas.
        if (ex.view_factors.coeff(i, it.col()) < 20.0 / double(mo.rays_per_node)) continue;
        ++total;
        inside += std::abs(it.value()) <= 3.29 * mc.standard_error.coeff(i, it.col()) + 1e-12;
      }
    sat << "| " << s.nodes().size() << " | exact, tolerance 1e-4, 2 threads (" << ex.pairs_occluded << " occluded pairs) | "
        << std::setprecision(3) << t_exact << " | " << std::scientific << std::setprecision(2)
        << ex.standard_error.coeffs().maxCoeff() << std::defaultfloat << " (estimate) | " << std::setprecision(4)
        << peakMiB() << " |\n"
        << "| " << s.nodes().size() << " | rays, 4,000 per node | " << std::setprecision(3) << mc.seconds << " | "
        << std::scientific << std::setprecision(2) << diff.coeffs().cwiseAbs().maxCoeff() << std::defaultfloat << " ("
        << inside << "/" << total << " within 3.29 σ) | " << std::setprecision(4) << peakMiB() << " |\n";
    Eigen::MatrixXd f;
    double dt = 0;
    const int n = static_cast<int>(s.nodes().size());
    if (!view3d.empty() && m <= 20 && runView3d(view3d, dir, cellSatellite(m), 1, 1e-4, n, f, dt))
      sat << "| " << n << " | View3D 4.0, eps 1e-4 (one thread, whole process) | " << std::setprecision(3) << dt
          << " | " << std::scientific << std::setprecision(2)
          << (f - Eigen::MatrixXd(ex.view_factors)).cwiseAbs().maxCoeff() << std::defaultfloat
          << " (against exact) | – |\n";
  }
  fs::remove_all(dir);
  std::ofstream csv(csv_path);
  csv << "scene,tool,setting,seconds,max_error\n";
  std::ostringstream md;
  md << "# Exact view factors against View3D\n\nGenerated by `make bench` "
        "(`build/bench/bench_exact_view_factors`). Machine: AMD EPYC, 2 cores, 24 GiB,\n"
     << "Debian 12, GCC 12 (`-O3 -march=native` for radnet, `-O3` for View3D as its build script has it).\n"
     << "One thread each. View3D is timed as its whole process (it reads its input and writes\n"
     << "its output file); radnet as the call of `exactViewFactors` (patch building included).\n"
     << "View3D writes 6 decimals, so its errors below 5e-7 read as that rounding.\n\n"
     << "Error: the room's largest |F − F_Howell| over its 30 node pairs (C-11, C-14); the\n"
     << "squares' |F − " << std::setprecision(10) << blocked_ref << "| (the exact method at tolerance 1e-12; View3D: 0.0995063).\n\n"
     << "| scene | tool | setting | time (s) | max error |\n|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << "| " << r.scene << " | " << r.tool << " | " << r.setting << " | " << std::setprecision(3) << r.seconds
       << " | " << std::scientific << std::setprecision(2) << r.error << std::defaultfloat << " |\n";
    csv << r.scene << "," << r.tool << "," << r.setting << "," << std::setprecision(6) << r.seconds << "," << r.error
        << "\n";
  }
  md << sat.str() << coverageSection();
  md << "\nThe plot `exact-view-factor-benchmark.png` (bench/plot_exact_benchmark.py) shows time against\nerror.\n";
  std::ofstream(md_path) << md.str();
  std::cout << md.str();
}
