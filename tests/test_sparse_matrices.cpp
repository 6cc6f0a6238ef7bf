// GR held as its factors (direct E G E sparse + E V (C − Λ) Vᵀ E) against the dense forms,
// the result file's sparse layout (CSR groups, GR factors) written and read back, the n × n
// matrices' chunks (shuffled where dense), and the memory estimate's sampled count of F's
// non-zeros.
#include "cases/config/errors.hpp"
#include "cases/config/work_estimate.hpp"
#include "cases/output/hdf5_chunks.hpp"
#include "cases/output/hdf5_layout.hpp"
#include "cases/output/hdf5_matrix_reader.hpp"
#include "cases/output/hdf5_writer.hpp"
#include "clustered_network.hpp"
#include "geometry/rays/view_factors.hpp"
#include "geometry/scene/primitives.hpp"
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/exchange.hpp"
#include "temp_dir.hpp"

#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <random>

using namespace radnet;
using radnet::test::clusteredNetwork;
using radnet::test::ClusteredNetwork;
using radnet::test::names;

namespace {

double largestDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("factored GR equals the dense forms: same pairs to round-off, all pairs the exact LU") {
  const int n = 1200;
  const ClusteredNetwork c = clusteredNetwork(n, 7);
  const solver::Network sparse(names(n), c.area, c.view_factors);
  const solver::Network dense(names(n), c.area, Eigen::MatrixXd(c.view_factors));
  REQUIRE(sparse.isSparse());
  REQUIRE_FALSE(dense.isSparse());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const Eigen::VectorXd eps = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
  const solver::EigenPairs all = solver::denseEigenPairs(dense.denseConductance());
  const Eigen::VectorXd rho = Eigen::VectorXd::Ones(n) - eps;
  const solver::ExchangeFactors exact = solver::exchangeFactorsDense(dense, eps);
  const double scale = exact.gr.cwiseAbs().maxCoeff();

  for (int k : {150, n}) {
    INFO("rank " << k);
    const solver::EigenPairs pairs = solver::truncate(all, k);
    const solver::ExchangeFactors factored =
        solver::exchangeFactorsLowRank(sparse, solver::LowRankBandSolver(sparse, pairs, rho), eps);
    const solver::ExchangeFactors formed =
        solver::exchangeFactorsLowRank(dense, solver::LowRankBandSolver(dense, pairs, rho), eps);
    REQUIRE(factored.status == solver::Status::Converged);
    REQUIRE(factored.factored());
    REQUIRE_FALSE(formed.factored());
    const Eigen::MatrixXd gr = factored.dense();
    // The same arithmetic up to the order of sums: round-off of a k-term product, ~k ε.
    CHECK(largestDifference(gr, formed.gr) <= 1e-12 * scale);
    CHECK((factored.gr_space - formed.gr_space).cwiseAbs().maxCoeff() <= 1e-12 * scale);
    CHECK(largestDifference(gr, gr.transpose()) == 0.0);
    // Every way of reading the factors agrees with the formed matrix.
    CHECK(std::abs(factored.entry(17, 18) - gr(17, 18)) <= 1e-14 * scale);
    CHECK(std::abs(factored.entry(5, 900) - gr(5, 900)) <= 1e-14 * scale);
    CHECK(largestDifference(factored.rows(100, 50), gr.middleRows(100, 50)) <= 1e-14 * scale);
    const Eigen::MatrixXd x = Eigen::MatrixXd::Random(n, 3);
    CHECK(largestDifference(factored.apply(x), gr * x) <= 1e-12 * scale * x.cwiseAbs().colwise().sum().maxCoeff());
    if (k == n) {  // every pair: the reflections exact, so GR is the LU's to the eigenvectors' round-off
      CHECK(largestDifference(gr, exact.gr) <= 1e-10 * scale);
      CHECK((factored.gr_space - exact.gr_space).cwiseAbs().maxCoeff() <= 1e-10 * scale);
    }
  }
}

TEST_CASE("result layout: CSR groups and GR factors read back bit for bit, damaged ones refused") {
  const int n = 300;
  const ClusteredNetwork c = clusteredNetwork(n, 11);
  const solver::Network net(names(n), c.area, c.view_factors);
  const Eigen::VectorXd eps = Eigen::VectorXd::Constant(n, 0.8);
  const solver::EigenPairs pairs = solver::truncate(solver::denseEigenPairs(net.denseConductance()), 40);
  const solver::ExchangeFactors ex =
      solver::exchangeFactorsLowRank(net, solver::LowRankBandSolver(net, pairs, Eigen::VectorXd::Ones(n) - eps), eps);
  REQUIRE(ex.factored());
  const solver::ExchangeFactors whole = solver::exchangeFactorsDense(net, eps);
  const cases::SparseRows f = net.sparseConductance();
  test::TempDir dir;
  const std::string path = (dir.path / "layout.h5").string();
  {
    cases::Hdf5Writer h5(path);
    h5.attribute("/meta", "program", std::string("radnet"));
    cases::writeCsr(h5, "/network/sparse/conductance", f, "m^2");
    cases::writeExchange(h5, "/network/", ex, false);
    cases::writeExchange(h5, "/optics/whole/", whole, true);
    // A hand-made CSR group whose row starts go back (row 1 would end before it begins).
    h5.writeVector("/broken/data", Eigen::Vector2d(1.0, 2.0), "1");
    h5.writeIntegers("/broken/indices", Eigen::Vector2i(0, 1), "1");
    h5.writeLongs("/broken/indptr", {0, 2, 1, 2}, "1");
    h5.commit();
  }
  const cases::Hdf5Reader h5(path);
  const cases::SparseRows back = cases::readCsr(h5, "/network/sparse/conductance", n, n);
  CHECK(Eigen::MatrixXd(back - f).cwiseAbs().maxCoeff() == 0.0);
  CHECK(back.nonZeros() == f.nonZeros());

  REQUIRE(cases::hasExchange(h5, "/network/"));
  CHECK(h5.has("/network/radiative_exchange/basis"));  // factors only, as asked: the name links to them
  const solver::ExchangeFactors read = cases::readExchange(h5, "/network/");
  REQUIRE(read.factored());
  CHECK(read.core.rows() == 40);
  CHECK(largestDifference(read.dense(), ex.dense()) == 0.0);
  CHECK((read.gr_space - ex.gr_space).cwiseAbs().maxCoeff() == 0.0);

  // Held whole: the dense dataset read, and its factors are the whole GR with k = 0.
  const solver::ExchangeFactors dense_read = cases::readExchange(h5, "/optics/whole/");
  CHECK_FALSE(dense_read.factored());
  CHECK(largestDifference(dense_read.gr, whole.gr) == 0.0);
  CHECK(h5.attribute("/optics/whole/radiative_exchange_factors", "rank", -1.0) == 0.0);
  CHECK(cases::readCsr(h5, "/optics/whole/radiative_exchange_factors/direct", n, n).nonZeros() > 0);

  // Shapes that do not fit are refused naming the dataset.
  CHECK_THROWS_AS(cases::readCsr(h5, "/network/sparse/conductance", n + 1, n), cases::InputError);
  CHECK_THROWS_WITH(cases::readCsr(h5, "/network/sparse/conductance", n, 10), Catch::Contains("/indices"));
  CHECK_THROWS_WITH(cases::readCsr(h5, "/broken", 3, 3), Catch::Contains("/broken/indptr"));
}

TEST_CASE("CSR written in place: a symmetric G from its column arrays, F's scaled rows by blocks") {
  // 2.4 M non-zeros: F's values are made by blocks of 2^20 entries, so rows straddle block
  // boundaries. Truth: G itself (converted to rows by Eigen) and G_ij / A_i by the same
  // product, bit for bit.
  const int n = 3000, per_row = 800;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> col(0, n - 1);
  std::uniform_real_distribution<double> value(0.01, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i)
    for (int e = 0; e < per_row / 2; ++e) entries.emplace_back(i, col(rng), value(rng));
  Eigen::SparseMatrix<double> half(n, n);
  half.setFromTriplets(entries.begin(), entries.end());
  // Symmetric bit for bit as the network's G = ½ (A F + (A F)ᵀ): a + b = b + a.
  const Eigen::SparseMatrix<double> g = Eigen::SparseMatrix<double>(half.transpose()) + half;
  REQUIRE(g.nonZeros() > (1 << 21));
  const Eigen::VectorXd area = Eigen::VectorXd::LinSpaced(n, 0.5, 3.0);
  const Eigen::VectorXd inverse_area = area.cwiseInverse();
  cases::SparseRows uncompressed(4, 4);  // Eigen's insert() leaves a matrix uncompressed
  uncompressed.insert(2, 1) = 5.0, uncompressed.insert(0, 3) = -1.5;
  REQUIRE_FALSE(uncompressed.isCompressed());

  test::TempDir dir;
  const std::string path = (dir.path / "in-place.h5").string();
  {
    cases::Hdf5Writer h5(path);
    h5.attribute("/meta", "program", std::string("radnet"));
    const Eigen::Map<const cases::SparseRows> rows = cases::rowsOfSymmetric(g);
    cases::writeNetworkMatrix(h5, "conductance", rows, "m^2", false);
    const cases::CsrPattern pattern("/network/sparse/conductance", rows);
    cases::writeNetworkMatrix(h5, "view_factors", rows, "1", false, inverse_area, pattern);
    cases::writeCsr(h5, "/small", uncompressed, "1");
    h5.commit();
  }
  const cases::Hdf5Reader h5(path);
  const cases::SparseRows g_rows = g;
  const cases::SparseRows g_back = cases::readCsr(h5, "/network/conductance", n, n);
  CHECK(g_back.nonZeros() == g.nonZeros());
  CHECK(Eigen::MatrixXd(g_back - g_rows).cwiseAbs().maxCoeff() == 0.0);
  const cases::SparseRows f_back = cases::readCsr(h5, "/network/view_factors", n, n);
  REQUIRE(f_back.nonZeros() == g.nonZeros());
  long long unequal = 0;  // compared with ==: x − a b would be contracted to one FMA (no rounding of a b)
  for (int i = 0; i < n; ++i)
    for (cases::SparseRows::InnerIterator it(f_back, i); it; ++it)
      unequal += it.value() != g_rows.coeff(i, it.col()) * inverse_area[i];
  CHECK(unequal == 0);
  CHECK(Eigen::MatrixXd(cases::readCsr(h5, "/small", 4, 4)) == Eigen::MatrixXd(uncompressed));
  CHECK_THROWS_AS(cases::rowsOfSymmetric(Eigen::SparseMatrix<double>(3, 4)), std::logic_error);
}

TEST_CASE("memory estimate: sampled rows' entries match the rows cast in full, within 3 standard errors") {
  // Two 2 × 2 m plates 0.5 m apart, each cut into 20 × 20 nodes: a cast row reaches some of
  // the 400 facing nodes, edge nodes fewer than central ones. Truth: every row cast with the
  // same rays; the 64 sampled rows' mean must lie within 3 standard errors (sd / √64) of it.
  geometry::Scene scene;
  const int cells = 20;
  const double side = 2.0 / cells;
  for (int plate = 0; plate < 2; ++plate)
    for (int a = 0; a < cells; ++a)
      for (int b = 0; b < cells; ++b) {
        const std::string name = std::to_string(plate) + "_" + std::to_string(a) + "_" + std::to_string(b);
        const geometry::Vec3 corner(a * side, b * side, 0.5 * plate);
        const geometry::Vec3 u(side, 0, 0), v(0, side, 0);
        scene.addSurface(name, name, plate == 0 ? geometry::rectangle(corner, u, v, 1, 1)
                                                : geometry::rectangle(corner, v, u, 1, 1), name, "");
      }
  const double rays = 2048;
  geometry::ViewFactorOptions all;
  all.rays_per_node = static_cast<std::int64_t>(rays);
  const geometry::RayCaster caster(scene);
  const geometry::ViewFactorResult full = geometry::computeViewFactors(caster, all);
  Eigen::ArrayXd per_row(full.view_factors.rows());
  for (Eigen::Index i = 0; i < per_row.size(); ++i) per_row[i] = double(full.view_factors.row(i).nonZeros());
  const double mean = per_row.mean();
  const double sd = std::sqrt((per_row - mean).square().sum() / double(per_row.size() - 1));
  const double sampled = cases::sampledRowEntries(scene, rays);
  INFO("full mean " << mean << ", sd " << sd << ", sampled " << sampled);
  REQUIRE(mean > 50.0);  // the rays reach many nodes: the estimate has something to find
  CHECK(std::abs(sampled - mean) <= 3.0 * sd / 8.0);
}

TEST_CASE("n × n chunks: dense ones shuffled, mostly-zero ones not, and HDF5 reads both back bit for bit") {
  // HDF5's shuffle on three 3-byte elements: byte b of element i goes to b × 3 + i; a
  // trailing byte (10 bytes, not 9) stays where it was.
  const std::vector<unsigned char> in{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  std::vector<unsigned char> out(in.size());
  cases::shuffleBytes(in.data(), in.size(), 3, out.data());
  CHECK(out == std::vector<unsigned char>{1, 4, 7, 2, 5, 8, 3, 6, 9, 10});

  // 600 × 600 in 256 × 256 chunks: chunk (0, 0) dense (random doubles), chunk (0, 1) one
  // entry in ten, chunk (1, 1) all zeros (not written: the fill value), the edge chunks
  // (rows 512 …) dense where the matrix reaches and zero-padded by HDF5.
  const Eigen::Index n = 600;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < 256; ++i)
    for (Eigen::Index j = 0; j < 256; ++j) m(i, j) = u(rng) * std::pow(10.0, 8.0 * u(rng));
  for (Eigen::Index i = 0; i < 256; ++i)
    for (Eigen::Index j = 256; j < 512; j += 10) m(i, j) = u(rng);
  for (Eigen::Index i = 512; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) m(i, j) = u(rng);
  test::TempDir dir;
  const std::string path = (dir.path / "chunks.h5").string();
  {
    cases::Hdf5Writer h5(path);
    h5.attribute("/meta", "program", std::string("radnet"));
    h5.writeMatrix("/m", m, "1");  // from 512 × 512 on: chunks compressed by radnet, not HDF5
    h5.commit();
  }
  const cases::Hdf5Reader h5(path);
  const Eigen::MatrixXd back = h5.matrix("/m");
  REQUIRE(back.rows() == n);
  CHECK((back.array() == m.array()).all());

  // Each written chunk's filter mask (bit 0: the shuffle skipped), read from the file.
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(file, "/m", H5P_DEFAULT);
  const hid_t dcpl = H5Dget_create_plist(ds);
  REQUIRE(H5Pget_nfilters(dcpl) == 2);
  unsigned flags = 0, config = 0;
  size_t cd_count = 0;
  CHECK(H5Pget_filter2(dcpl, 0, &flags, &cd_count, nullptr, 0, nullptr, &config) == H5Z_FILTER_SHUFFLE);
  const auto maskAt = [&](hsize_t row, hsize_t col) {
    const hsize_t offset[2] = {row, col};
    unsigned mask = 99;
    haddr_t address = 0;
    hsize_t bytes = 0;
    return H5Dget_chunk_info_by_coord(ds, offset, &mask, &address, &bytes) >= 0 && bytes > 0 ? int(mask) : -1;
  };
  CHECK(maskAt(0, 0) == 0);      // dense: shuffled, then deflated
  CHECK(maskAt(0, 256) == 1);    // one entry in ten: deflated as it is
  CHECK(maskAt(256, 256) == -1);  // zeros: never written
  CHECK(maskAt(512, 512) == 1);  // an edge chunk counts HDF5's padding: 88 × 88 of 256 × 256 filled
  H5Pclose(dcpl);
  H5Dclose(ds);
  H5Fclose(file);
}

TEST_CASE("σ_F held in float on F's pattern is written as the doubles it holds, dense and CSR, at every size") {
  // writeRawViewFactors with ViewFactorEstimate::errors_on_pattern: the (n,n) dataset by the
  // small path (5 nodes) and by compressed chunks (600 nodes: 256 × 256 chunks), and the CSR
  // group whose indices are the raw F's.
  for (const int n : {5, 600}) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j && u(rng) < 0.3) entries.emplace_back(i, j, 0.01 * u(rng));
    geometry::ViewFactorEstimate est;
    est.view_factors.resize(n, n);
    est.view_factors.setFromTriplets(entries.begin(), entries.end());
    est.view_factors.makeCompressed();
    est.error_on_pattern.resize(est.view_factors.nonZeros());
    for (Eigen::Index k = 0; k < est.error_on_pattern.size(); ++k)
      est.error_on_pattern[k] = static_cast<float>(1e-5 * (1.0 + u(rng)));  // seven digits each
    est.errors_on_pattern = true;
    const Eigen::MatrixXd sigma = Eigen::MatrixXd(geometry::errorsOnPattern(est).cast<double>());
    for (const bool dense : {true, false}) {
      INFO("n = " << n << (dense ? ", dense and CSR" : ", CSR only"));
      test::TempDir dir;
      const std::string path = (dir.path / "raw.h5").string();
      {
        cases::Hdf5Writer h5(path);
        h5.attribute("/meta", "program", std::string("radnet"));
        cases::writeRawViewFactors(h5, est, dense);
        h5.commit();
      }
      const cases::Hdf5Reader h5(path);
      const cases::SparseRows csr = cases::readCsr(h5, "/network/sparse/view_factor_stderr", n, n);
      CHECK(csr.nonZeros() == est.view_factors.nonZeros());
      CHECK((Eigen::MatrixXd(csr) - sigma).cwiseAbs().maxCoeff() == 0.0);
      CHECK((Eigen::MatrixXd(cases::readCsr(h5, "/network/sparse/view_factors_raw", n, n)) -
             Eigen::MatrixXd(est.view_factors))
                .cwiseAbs()
                .maxCoeff() == 0.0);
      if (dense) CHECK((h5.matrix("/network/view_factor_stderr") - sigma).cwiseAbs().maxCoeff() == 0.0);
    }
  }
}
