#pragma once
// The `output:` block of a case (docs/case-files.md, "Output"): which n × n matrices the
// result file also holds densely. Every matrix is in the file at every size in compressed
// sparse rows (/network/sparse, docs/hdf5-layout.md, "Matrices"), GR as its direct part and
// low-rank factors when it was formed from the eigenpairs.
#include "cases/config/yaml_document.hpp"

#include <optional>

namespace radnet::cases {

/// Up to this many radiative nodes the (n,n) datasets (/network/view_factors, …,
/// /network/radiative_exchange) are written too: 200 MB a matrix before compression. Past
/// it, for a sparse network, a dense GR would cost n² of memory and most of the write (on
/// the 19,202-node satellite 753 of the file's 941 MB and 6.6 of its 12.6 s), F is 1–4 %
/// non-zero, and readers take the sparse and factored forms.
inline constexpr long kDenseOutputMaxNodes = 5000;

/// Each key: absent, the (n,n) datasets up to kDenseOutputMaxNodes, and at any size for
/// matrices held dense in memory anyway (a dense network's F and G, a GR not factored: there
/// the (n,n) form is the compact one); true, at every size; false, never (the sparse and
/// factored forms only).
struct OutputSettings {
  std::optional<bool> dense_matrices;          ///< `dense_matrices`: F, raw F, σ_F and G as (n,n)
  std::optional<bool> dense_exchange_factors;  ///< `dense_exchange_factors`: GR as (n,n)
  bool denseMatrices(long n, bool held_dense) const {
    return dense_matrices.value_or(held_dense || n <= kDenseOutputMaxNodes);
  }
  bool denseExchange(long n, bool held_dense) const {
    return dense_exchange_factors.value_or(held_dense || n <= kDenseOutputMaxNodes);
  }
};

/// Parses `output:` of the case root (defaults when absent). @throws InputError with file:line:column
OutputSettings parseOutputSettings(const YamlDocument& doc, const YAML::Node& root);

}  // namespace radnet::cases
