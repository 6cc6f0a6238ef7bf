"""One backward-Euler step of a thermal network, written independently of radnet's C++ solver:
the second method the export and import tests compare radnet's transients against.

    C (T − T_old)/dt = q + Σ_j GL_ij (T_j − T_i) + σ Σ_j GR_ij (T_j⁴ − T_i⁴)

for the free nodes; `fixed` nodes keep the values `guess` gives them (boundary temperatures).
Newton to |ΔT| < 1e-10 K.
"""
import numpy as np


def backward_euler_step(t_old, guess, q, gl, gr, c, sigma, fixed, dt, iterations=30):
    new = np.array(guess, dtype=float)
    for _ in range(iterations):
        r = q + gl @ new - gl.sum(1) * new + sigma * (gr @ new**4 - gr.sum(1) * new**4) - c * (new - t_old) / dt
        jac = gl - np.diag(gl.sum(1)) + sigma * (4 * gr * new**3 - np.diag(4 * gr.sum(1) * new**3)) - np.diag(c / dt)
        r[fixed] = 0.0
        jac[fixed] = 0.0
        jac[fixed, fixed] = 1.0
        delta = np.linalg.solve(jac, -r)
        new += delta
        if np.abs(delta).max() < 1e-10:
            break
    return new
