"""Reading radnet's n × n matrices from a result file, the same way at every size.

Every matrix of /network is stored in compressed sparse rows (scipy's CSR convention) under
/network/sparse/<name>: `data` (nnz), `indices` (nnz, the column of each entry), `indptr`
(n + 1: row i is data[indptr[i]:indptr[i+1]]) and the attribute `shape`. GR is stored as
its factors, GR = direct + basis @ core @ basis.T (`direct` a CSR group; `basis` n × k and
`core` k × k the reflected part from the rank-k eigenpairs; k = 0 when GR was formed whole).
Up to 5,000 radiative nodes, for matrices radnet holds densely (a dense network, a GR not
factored), or with `output: {dense_matrices: true}` / `{dense_exchange_factors: true}`, the
(n, n) datasets /network/view_factors, …, /network/radiative_exchange are there as well;
without them those names are links to the CSR group and to GR's factors. Past 5,000 nodes a
matrix 25 % or more non-zero that has its (n, n) dataset (a closed room's) is not also in
CSR: the functions below then return the dense form.
docs/hdf5-layout.md, "Matrices".

    import h5py, radnet_matrices as rm
    with h5py.File("out.h5") as f:
        F = rm.csr(f, "view_factors")           # scipy.sparse.csr_matrix if scipy is there, else dense numpy
        row = rm.exchange_row(f, 17)           # GR[17, :] in m², never forming GR
        GR = rm.exchange_dense(f)              # the whole GR (n × n, 8 n² bytes)

Only numpy is needed; scipy is used when present. Run as a script on a result to print its
matrices' sizes and check that the stored forms agree where both are present:
    /usr/bin/python3 docs/radnet_matrices.py out.h5
"""
import sys

import numpy as np


def _parts(group):
    return group["data"][()], group["indices"][()].astype(np.int64), group["indptr"][()].astype(np.int64)


def csr_group(f, path):
    """The CSR group at `path` (e.g. "/network/sparse/view_factors") as a scipy csr_matrix,
    or as a dense numpy array when scipy is not installed."""
    g = f[path]
    data, indices, indptr = _parts(g)
    shape = tuple(int(s) for s in g.attrs["shape"])
    try:
        import scipy.sparse
        return scipy.sparse.csr_matrix((data, indices, indptr), shape=shape)
    except ImportError:
        dense = np.zeros(shape)
        for i in range(shape[0]):
            dense[i, indices[indptr[i]:indptr[i + 1]]] += data[indptr[i]:indptr[i + 1]]
        return dense


def csr(f, name):
    """/network/sparse/<name>: view_factors, view_factors_raw, view_factor_stderr, conductance.
    A matrix more than 25 % non-zero past 5,000 nodes (a closed room's) has only its (n, n)
    dataset: it is returned as the dense numpy array."""
    if "/network/sparse/" + name not in f:
        return f["/network/" + name][()]
    return csr_group(f, "/network/sparse/" + name)


def csr_row(f, path, i):
    """Row i of the CSR group at `path` as a dense vector, reading only that row."""
    g = f[path]
    start, end = (int(x) for x in g["indptr"][i:i + 2])
    row = np.zeros(int(g.attrs["shape"][1]))
    np.add.at(row, g["indices"][start:end].astype(np.int64), g["data"][start:end])
    return row


def exchange_row(f, i, prefix="/network/"):
    """GR[i, :] (m²) of `prefix` ("/network/", "/optics/<set>/", "/articulation/configuration_<k>/"):
    direct row + basis[i] @ core @ basis.T, O(n k)."""
    if prefix + "radiative_exchange_factors" not in f:  # held whole past 5,000 nodes: the (n, n) GR
        return f[prefix + "radiative_exchange"][i, :]
    factors = f[prefix + "radiative_exchange_factors"]
    row = csr_row(f, prefix + "radiative_exchange_factors/direct", i)
    basis = factors["basis"]
    if basis.shape[1] > 0:
        row += (basis[i, :] @ factors["core"][()]) @ basis[()].T
    return row


def exchange_dense(f, prefix="/network/"):
    """The whole GR (n × n, m²) from its factors (or its (n, n) dataset when it has no factors)."""
    if prefix + "radiative_exchange_factors" not in f:
        return f[prefix + "radiative_exchange"][()]
    factors = f[prefix + "radiative_exchange_factors"]
    data, indices, indptr = _parts(factors["direct"])
    n = len(indptr) - 1
    basis = factors["basis"][()].reshape(n, -1)
    gr = basis @ factors["core"][()].reshape(basis.shape[1], basis.shape[1]) @ basis.T if basis.shape[1] else np.zeros((n, n))
    rows = np.repeat(np.arange(n), np.diff(indptr))
    np.add.at(gr, (rows, indices), data)
    return gr


def main(path):
    import h5py
    with h5py.File(path, "r") as f:
        n = len(f["/network/gr_space"]) if "/network/gr_space" in f else None
        worst = 0.0
        for name in ("view_factors", "view_factors_raw", "view_factor_stderr", "conductance"):
            if "/network/sparse/" + name not in f:
                continue
            g = f["/network/sparse/" + name]
            nnz, shape = len(g["data"]), tuple(g.attrs["shape"])
            print(f"{name}: {shape[0]} × {shape[1]}, {nnz} non-zero ({nnz / max(1, shape[0] * shape[1]):.2%})")
            if isinstance(f.get("/network/" + name), h5py.Dataset):  # else a link to the CSR group
                dense = f["/network/" + name][()]
                stored = csr(f, name)
                stored = stored.toarray() if hasattr(stored, "toarray") else stored
                worst = max(worst, float(np.max(np.abs(dense - stored))))
        if n is not None and "/network/radiative_exchange_factors" in f:
            k = f["/network/radiative_exchange_factors/basis"].shape[1]
            print(f"GR: {n} nodes, direct part {len(f['/network/radiative_exchange_factors/direct/data'])} non-zero, rank {k}")
            if isinstance(f.get("/network/radiative_exchange"), h5py.Dataset):
                scale = float(np.max(np.abs(f["/network/radiative_exchange"][()]))) or 1.0
                worst = max(worst, float(np.max(np.abs(exchange_dense(f) - f["/network/radiative_exchange"][()]))) / scale)
        print(f"largest difference between the dense and the sparse/factored forms: {worst:.3g}")
        return 0 if worst < 1e-12 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
