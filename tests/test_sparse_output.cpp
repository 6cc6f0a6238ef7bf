// The result file's matrices through `radnet run`: the sparse and factored forms are always
// there and say what the dense ones say; without the dense ones, export and the Python
// helper (docs/radnet_matrices.py) still read GR.
#include "cases/output/hdf5_matrix_reader.hpp"
#include "cli_support.hpp"

using namespace radnet;
using namespace radnet::test;

namespace {

// The CubeSat (11 radiative nodes, F 8 % non-zero: a sparse network) with GR from the
// eigenpairs (refine: false), so GR is held as its factors, plus `extra` lines.
void writeCase(const TempDir& dir, const std::string& name, const std::string& extra) {
  std::string text = slurp(source("cases/examples/cubesat-3u.yaml"));
  const std::string rays = "  view_factors: {rays: 50000, seed: 1}\n";
  const size_t at = text.find(rays);
  REQUIRE(at != std::string::npos);
  text.insert(at + rays.size(), "  refine: false\n");
  std::ofstream(dir.path / name) << text << extra;
}

int countLines(const std::string& text, const std::string& start) {
  int count = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) count += line.rfind(start, 0) == 0;
  return count;
}

}  // namespace

TEST_CASE("sparse and factored matrices agree with the dense ones, and export and the helper read the factors") {
  TempDir dir;
  writeCase(dir, "dense.yaml", "");
  writeCase(dir, "sparse.yaml", "output: {dense_matrices: false, dense_exchange_factors: false}\n");
  REQUIRE(runRadnet("run dense.yaml -o dense.h5 -q", dir).exit_code == 0);
  REQUIRE(runRadnet("run sparse.yaml -o sparse.h5 -q", dir).exit_code == 0);

  const cases::Hdf5Reader dense((dir.path / "dense.h5").string()), sparse((dir.path / "sparse.h5").string());
  // No (n,n) dataset: the names link to the CSR group and to GR's factors.
  CHECK(sparse.has("/network/view_factors/indptr"));
  CHECK(sparse.has("/network/radiative_exchange/direct/indptr"));
  CHECK(dense.has("/network/view_factors"));  // 11 nodes: below kDenseOutputMaxNodes
  const Eigen::Index n = sparse.rows("/network/gr_space");
  REQUIRE(n == 11);
  // The same rays: F in CSR is the dense F entry for entry.
  for (const char* name : {"view_factors", "view_factors_raw", "view_factor_stderr", "conductance"}) {
    INFO(name);
    const Eigen::MatrixXd from_csr(cases::readCsr(sparse, std::string("/network/sparse/") + name, n, n));
    CHECK((from_csr - dense.matrix(std::string("/network/") + name)).cwiseAbs().maxCoeff() == 0.0);
  }
  const solver::ExchangeFactors factors = cases::readExchange(sparse, "/network/");
  REQUIRE(factors.factored());
  CHECK(factors.core.rows() > 0);  // from the pairs
  const Eigen::MatrixXd gr = dense.matrix("/network/radiative_exchange");
  // The dense dataset is formed from the same factors: round-off of a k-term sum.
  CHECK((factors.dense() - gr).cwiseAbs().maxCoeff() <= 1e-13 * gr.cwiseAbs().maxCoeff());
  // Optical set links: /optics/base/ reads as /network/.
  CHECK((cases::readExchange(sparse, "/optics/base/").dense() - factors.dense()).cwiseAbs().maxCoeff() == 0.0);

  // Export from the factors gives the deck the dense GR gives (same couplings kept).
  const Run a = runRadnet("export dense.h5 --format esatan -o dense.d", dir);
  const Run b = runRadnet("export sparse.h5 --format esatan -o sparse.d", dir);
  REQUIRE(a.exit_code == 0);
  REQUIRE(b.exit_code == 0);
  const std::string deck_a = slurp(dir.path / "dense.d"), deck_b = slurp(dir.path / "sparse.d");
  CHECK(countLines(deck_a, "  GR(") > 0);
  CHECK(countLines(deck_a, "  GR(") == countLines(deck_b, "  GR("));

  // The documented Python helper reads both forms and finds them equal (exit 0).
  const std::string helper = "/usr/bin/python3 '" + source("docs/radnet_matrices.py") + "' '" + (dir.path / "dense.h5").string() +
                             "' > '" + (dir.path / "helper.txt").string() + "' 2>&1";
  const int status = std::system(helper.c_str());
  INFO(slurp(dir.path / "helper.txt"));
  CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 0);
  CHECK_THAT(slurp(dir.path / "helper.txt"), Catch::Contains("rank"));
}

TEST_CASE("temperatures from the factored GR (all pairs) equal those from the exact dense GR") {
  TempDir dir;
  writeCase(dir, "factored.yaml", "");  // refine: false: GR from the pairs, held as factors
  std::ofstream(dir.path / "lu.yaml") << slurp(source("cases/examples/cubesat-3u.yaml"));  // refined: exact dense GR
  REQUIRE(runRadnet("run factored.yaml -o factored.h5 -q", dir).exit_code == 0);
  REQUIRE(runRadnet("run lu.yaml -o lu.h5 -q", dir).exit_code == 0);
  const cases::Hdf5Reader factored((dir.path / "factored.h5").string()), lu((dir.path / "lu.h5").string());
  REQUIRE(factored.attribute("/network/radiative_exchange_factors", "rank", 0.0) == 11.0);  // every pair: exact
  REQUIRE(lu.textAttribute("/network/radiative_exchange", "method", "") == "dense Cholesky");  // every ε < 1
  const Eigen::MatrixXd gr_lu = lu.matrix("/network/radiative_exchange");
  const Eigen::MatrixXd gr_factored = cases::readExchange(factored, "/network/").dense();
  // All 11 pairs kept: the two GR differ by the eigenvectors' round-off only.
  CHECK((gr_factored - gr_lu).cwiseAbs().maxCoeff() <= 1e-10 * gr_lu.cwiseAbs().maxCoeff());
  // The band solves differ (refined to 1e-10 against the rank-11 answer), so the loads do by
  // that much: temperatures within 1e-6 K (δT ≈ δQ / (4 ε σ T³ A) with δQ ~ 1e-10 of the loads).
  const Eigen::MatrixXd t_factored = factored.matrix("/solution/temperature"), t_lu = lu.matrix("/solution/temperature");
  REQUIRE(t_factored.rows() == t_lu.rows());
  CHECK((t_factored - t_lu).cwiseAbs().maxCoeff() <= 1e-6);
}

TEST_CASE("past 5,000 nodes a sparse network writes no (n,n) dataset: the names link to CSR and factors") {
  // 5,400 coplanar nodes: F = 0, G = 0, no eigenpair (k = 0: the factored GR's empty core was
  // once a segfault), GR = diag(ε A) to space only.
  TempDir dir;
  std::ofstream(dir.path / "plate.yaml")
      << "name: plate-5400\nmaterials:\n  white: {emissivity: 0.8, absorptivity: 0.2}\ngeometry:\n"
         "  - rectangle: {name: plate, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: white, nodes: [75, 72]}\n";
  const Run run = runRadnet("run plate.yaml -o plate.h5 -q", dir);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const cases::Hdf5Reader h5((dir.path / "plate.h5").string());
  const Eigen::Index n = h5.rows("/network/gr_space");
  REQUIRE(n == 5400);
  for (const char* name : {"view_factors", "view_factors_raw", "view_factor_stderr", "conductance"}) {
    INFO(name);
    CHECK(h5.has(std::string("/network/") + name + "/indptr"));  // the link to the CSR group
    CHECK(cases::readCsr(h5, std::string("/network/sparse/") + name, n, n).nonZeros() == 0);
  }
  const solver::ExchangeFactors gr = cases::readExchange(h5, "/network/");
  REQUIRE(gr.factored());
  CHECK(gr.core.rows() == 0);
  const double area = 1.0 / 5400.0;  // m²
  CHECK((gr.gr_space.array() - 0.8 * area).abs().maxCoeff() <= 1e-15);
  CHECK(gr.rows(0, 10).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("σ_F kept in float on F's pattern is written as the σ every other path writes") {
  // A closed box of 6 × 4 nodes by the exact method: without an orbit or temperatures nothing
  // reads σ after the raw estimate, which then holds σ in float on F's pattern
  // (ViewFactorEstimate::error_on_pattern); with a thermal block σ is a matrix of its own.
  // The two files must hold the same σ, dense and CSR, and the same raw F.
  TempDir dir;
  std::string box = "name: box\nmaterials:\n  grey: {emissivity: 0.9, absorptivity: 0.5}\ngeometry:\n";
  const char* faces[6][4] = {
      {"floor", "[0, 0, 0]", "[1, 0, 0]", "[0, 0.8, 0]"}, {"ceil", "[0, 0, 0.6]", "[0, 0.8, 0]", "[1, 0, 0]"},
      {"wx0", "[0, 0, 0]", "[0, 0.8, 0]", "[0, 0, 0.6]"}, {"wx1", "[1, 0, 0]", "[0, 0, 0.6]", "[0, 0.8, 0]"},
      {"wy0", "[0, 0, 0]", "[0, 0, 0.6]", "[1, 0, 0]"},   {"wy1", "[0, 0.8, 0]", "[1, 0, 0]", "[0, 0, 0.6]"}};
  for (const auto& f : faces)
    box += std::string("  - rectangle: {name: ") + f[0] + ", origin: " + f[1] + ", u: " + f[2] + ", v: " + f[3] +
           ", front: grey, nodes: [2, 2]}\n";
  const std::string output = "output: {dense_matrices: true}\n";
  std::ofstream(dir.path / "bare.yaml") << box << output;
  std::ofstream(dir.path / "warm.yaml")
      << box << output << "thermal:\n  nodes:\n    floor.0.0: {temperature: 300.0}\n    ceil.0.0: {dissipation: 1.0}\n";
  for (const char* name : {"bare", "warm"}) {
    const Run run = runRadnet(std::string("run ") + name + ".yaml -o " + name + ".h5 -q", dir);
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
  }
  const cases::Hdf5Reader bare((dir.path / "bare.h5").string()), warm((dir.path / "warm.h5").string());
  const Eigen::Index n = bare.rows("/network/gr_space");
  REQUIRE(n == 24);
  const Eigen::MatrixXd sigma = bare.matrix("/network/view_factor_stderr");
  CHECK(sigma.maxCoeff() > 0);
  CHECK((sigma - warm.matrix("/network/view_factor_stderr")).cwiseAbs().maxCoeff() == 0.0);
  CHECK((Eigen::MatrixXd(cases::readCsr(bare, "/network/sparse/view_factor_stderr", n, n)) - sigma)
            .cwiseAbs()
            .maxCoeff() == 0.0);
  // Every σ is a float's value (kept to seven digits on either path).
  CHECK((sigma.cast<float>().cast<double>() - sigma).cwiseAbs().maxCoeff() == 0.0);
  // σ sits where the raw F does: F ≠ 0 exactly where σ's CSR has an entry.
  const Eigen::MatrixXd raw = bare.matrix("/network/view_factors_raw");
  const Eigen::SparseMatrix<double, Eigen::RowMajor> sigma_csr =
      cases::readCsr(bare, "/network/sparse/view_factor_stderr", n, n);
  CHECK(sigma_csr.nonZeros() == (raw.array() != 0.0).count());
  // The bare run holds each pair once (ViewFactorEstimate::upper_exchange): the same raw F,
  // and a corrected F whose weights are the pairs' variances rounded to float (6e-8 of
  // each): on moves of at most the correction's largest, the two agree to 1e-7 of it.
  CHECK((raw - warm.matrix("/network/view_factors_raw")).cwiseAbs().maxCoeff() == 0.0);
  const double largest_move = warm.attribute("/network", "correction_max_change", -1.0);
  CHECK(largest_move > 0);
  CHECK((bare.matrix("/network/view_factors") - warm.matrix("/network/view_factors")).cwiseAbs().maxCoeff() <=
        1e-7 * largest_move + 1e-16);
}

TEST_CASE("output: keys are checked at their line") {
  TempDir dir;
  writeCase(dir, "bad.yaml", "output: {dense_matrix: true}\n");
  const Run r = runRadnet("run bad.yaml -o bad.h5 -q", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("bad.yaml:") && Catch::Contains("dense_matrix"));
  writeCase(dir, "worse.yaml", "output: {dense_matrices: maybe}\n");
  CHECK(runRadnet("run worse.yaml -o worse.h5 -q", dir).exit_code == 2);
}

TEST_CASE("a 1,602-node transient on the factored GR equals the dense LU's end to end") {
  TempDir dir;
  const std::string text = slurp(source("tests/data/factored/satellite-1602-thermal.yaml"));
  const std::string flat = "  dish_paint:  {emissivity: 0.88, absorptivity: 0.20}";
  const size_t at = text.find(flat);
  REQUIRE(at != std::string::npos);
  std::string dense = text;
  // The same ε as a table: optics that follow temperature keep GR dense (the ε(T) update).
  dense.replace(at, flat.size(), "  dish_paint:  {emissivity: {table: [[100.0, 0.88], [500.0, 0.88]]}, absorptivity: 0.20}");
  std::ofstream(dir.path / "factored.yaml") << text;
  std::ofstream(dir.path / "dense.yaml") << dense;
  const Run factored = runRadnet("run factored.yaml -o factored.h5", dir);
  REQUIRE(factored.exit_code == 0);
  const Run lu = runRadnet("run dense.yaml -o dense.h5", dir);
  REQUIRE(lu.exit_code == 0);
  // Each took the path it should (the test would otherwise compare a path with itself).
  CHECK(factored.err.find("GR factored, rank") != std::string::npos);
  CHECK(lu.err.find("GR factored") == std::string::npos);
  const cases::Hdf5Reader a((dir.path / "factored.h5").string()), b((dir.path / "dense.h5").string());
  const Eigen::MatrixXd t_factored = a.matrix("/solution/temperature"), t_dense = b.matrix("/solution/temperature");
  REQUIRE(t_factored.rows() == t_dense.rows());
  REQUIRE(t_factored.cols() == 1602);
  // The same GR (the dense one formed from the same factors) and the same steps: what differs
  // is each step's linear solve, GMRES to 1e-10 against LU. Measured 2.3e-13 K; allowed 1e-9 K
  // (1e-11 of 200–360 K).
  CHECK((t_factored - t_dense).cwiseAbs().maxCoeff() <= 1e-9);
}
