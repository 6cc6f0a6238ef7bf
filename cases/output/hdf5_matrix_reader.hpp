#pragma once
// The n × n matrices of a result read back (docs/hdf5-layout.md, "Matrices"): a CSR group,
// and GR from its (n,n) dataset or, without one, from its factors. Every part is checked
// (shapes, indptr from 0 to nnz without decreasing, column indices in range, values
// finite) before it is used: a damaged or foreign file is an InputError naming the dataset.
#include "cases/output/hdf5_matrices.hpp"
#include "cases/output/hdf5_reader.hpp"

#include <string>

namespace radnet::cases {

/// The CSR group `group` (data, indices, indptr) of a rows × cols matrix.
SparseRows readCsr(const Hdf5Reader& h5, const std::string& group, Eigen::Index rows, Eigen::Index cols);

/// True when the file holds GR under `prefix` ("/network/", "/optics/<set>/",
/// "/articulation/configuration_<k>/"), in either form.
bool hasExchange(const Hdf5Reader& h5, const std::string& prefix);

/// GR and GR to space under `prefix`: the (n,n) dataset when present (held dense), else the
/// factors (held factored: rows are formed as they are asked for). n = size of gr_space.
solver::ExchangeFactors readExchange(const Hdf5Reader& h5, const std::string& prefix);

}  // namespace radnet::cases
