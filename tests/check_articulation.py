#!/usr/bin/python3
"""Turning parts (articulation:) equal runs with the parts turned by hand.

usage: check_articulation.py RADNET SOURCE_DIR WORK_DIR

The tracking-wings example (cases/examples/tracking-wings.yaml: a 1 m bus, two wings on ±y
arms turned about the body y axis) is run

1. with the drive held by an angle table at one angle (30°, −130°, 90°), against the same
   case with the wings' rectangles turned by hand in the file. With `method: monte_carlo` and
   one seed both runs cast the same rays from the same points (the recast rows of the
   articulated run are the hand run's rows): F, loads, GR and temperatures agree to 1e-9 of
   their largest magnitude (rays that graze an edge, whose corners differ by the rounding of
   the rotation, may land differently: that is the tolerance's room);
2. the same at the default settings: temperatures within 4 × their combined 1σ + 0.05 K,
   absorbed powers within 4 × combined σ + 1e-3 of the largest (and so flown inertial, where
   the loads come from sky kernels, not rays at every position); and where the articulated
   run integrated every turning row again (no ray traced in its configurations: this example
   at its defaults), the same exact method on the same geometry as the hand run: GR and
   temperatures to 1e-9 of their largest (the vertices' rounding apart);
3. tracking the Sun: every angle a multiple of the 10° step, within 5° of the exact
   tracking angle (sunlit positions) from /orbit/sun_body, eclipse holding the last sunlit
   angle, one eigendecomposition for every configuration, the configurations' angles the
   distinct binned angles; the positions of two configurations equal, to 1e-9, a hand run
   at that angle (same rays again); `radnet export` of a turned position writes its
   configuration's GR; and the XDMF steps point at their configuration's vertices.
"""
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np

RADNET, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(WORK, exist_ok=True)
failures = []
EXAMPLE = open(os.path.join(SOURCE, "cases/examples/tracking-wings.yaml")).read()
ROOTS = {"wing_py": (-0.5, 0.7, 0.0), "wing_my": (-0.5, -2.2, 0.0)}
MONTE_CARLO = "solver:\n  view_factors: {method: monte_carlo, rays: 20000, seed: 3}\n"


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL", what)


def run(name, text):
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(WORK, name + ".h5")
    r = subprocess.run([RADNET, "run", path, "-o", out], capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
        raise SystemExit(name + ": exit %d" % r.returncode)
    return h5py.File(out, "r")


def with_angle(text, degrees):
    return text.replace("    track: sun\n", "    angles: [[0, %g], [1.0e6, %g]]\n" % (degrees, degrees))


def turned_by_hand(text, degrees):
    """The wings' rectangles turned about the body y axis through the origin (right-handed)."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    turn = lambda x, y, z: "[%.17g, %.17g, %.17g]" % (c * x + s * z, y, -s * x + c * z)
    text = text[:text.index("\narticulation:\n") + 1] + text[text.index("\norbit:\n") + 1:]
    for name, (x, y, z) in ROOTS.items():
        old = "name: %s, origin: [%g, %g, %g], u: [1, 0, 0]" % (name, x, y, z)
        assert old in text, "the example's wings changed: update this test"
        text = text.replace(old, "name: %s, origin: %s, u: %s" % (name, turn(x, y, z), turn(1, 0, 0)))
    return text


def largest(a):
    return max(np.abs(a).max(), 1e-300)


def same(a, b, what, relative=1e-9, columns=None):
    a, b = np.asarray(a), np.asarray(b)
    if columns is not None:
        a, b = a[columns], b[columns]
    err = np.abs(a - b).max() / largest(b)
    check(err <= relative, "%s: differs by %.3g of its largest magnitude (allowed %g)" % (what, err, relative))


LOADS = ["loads/solar", "loads/albedo", "loads/earth_ir"]

# 1. One angle, the same rays: equal.
for degrees in (30, -130, 90):
    art = run("mc_art_%d" % degrees, with_angle(EXAMPLE, degrees) + MONTE_CARLO)
    hand = run("mc_hand_%d" % degrees, turned_by_hand(EXAMPLE, degrees) + MONTE_CARLO)
    check(list(art["articulation/configuration_angle"][:, 0]) == [0.0, float(degrees)],
          "%d°: configurations %s" % (degrees, art["articulation/configuration_angle"][:, 0]))
    check(art["report"].attrs["eigendecompositions"] == 1, "%d°: one eigendecomposition" % degrees)
    for key in LOADS + ["solution/temperature"]:
        same(art[key][:], hand[key][:], "%d°, %s" % (degrees, key))
    same(art["articulation/configuration_1/radiative_exchange"][:], hand["network/radiative_exchange"][:], "%d°, GR" % degrees)
    same(art["articulation/vertices"][1], hand["geometry/vertices"][:], "%d°, vertices" % degrees, 1e-12)

def within_error_bars(art, hand, label):
    """Temperatures within 4 × their combined σ + 0.05 K, absorbed powers within 4 × theirs +
    1e-3 of the largest."""
    t, th = art["solution/temperature"][:], hand["solution/temperature"][:]
    sigma = np.hypot(art["uncertainty/temperature"][:], hand["uncertainty/temperature"][:])
    worst = (np.abs(t - th) - 4 * sigma).max()
    check(worst <= 0.05, "%s: a temperature differs by %.3g K beyond 4σ" % (label, worst))
    q = sum(art[k][:] for k in LOADS)
    qh = sum(hand[k][:] for k in LOADS)
    sigma = np.hypot(art["uncertainty/absorbed_power"][:], hand["uncertainty/absorbed_power"][:])
    worst = (np.abs(q - qh) - 4 * sigma).max() / largest(qh)
    check(worst <= 1e-3, "%s: an absorbed power differs by %.3g of the largest beyond 4σ" % (label, worst))


# 2. Default settings: independent estimates, within their error bars.
for degrees in (30, -130):
    art = run("art_%d" % degrees, with_angle(EXAMPLE, degrees))
    hand = run("hand_%d" % degrees, turned_by_hand(EXAMPLE, degrees))
    within_error_bars(art, hand, "%d°, default settings" % degrees)
    integrated = art["report"].attrs["articulation_integrated_rows"]
    check(integrated > 0, "%d°, default settings: no turning row integrated again" % degrees)
    if art["report"].attrs["articulation_rays"] == 0:
        same(art["articulation/configuration_1/radiative_exchange"][:], hand["network/radiative_exchange"][:],
             "%d°, default settings, GR" % degrees)
        same(t, th, "%d°, default settings, temperatures" % degrees)

# 2b. Flown inertial, the planet moving in the body frame: the loads come from sky kernels
# (one for the rows no turn changes, one a configuration for the turning rows) as in a run
# without turning parts, not from planet rays cast again at every position (which took the
# 2,006-node wing model's loads from 1 s to 59 s), and agree with the hand run's.
INERTIAL = "attitude: {mode: inertial, quaternion: [1, 0, 0, 0]}"
inertial = EXAMPLE.replace("attitude: {mode: nadir}", INERTIAL)
assert inertial != EXAMPLE, "the example's attitude changed: update this test"
art = run("inertial_art", with_angle(inertial, 30))
hand = run("inertial_hand", turned_by_hand(inertial, 30))
kernel_rays, planet_rays = (int(art["report"].attrs[k]) for k in ("sky_kernel_rays", "planet_rays"))
check(kernel_rays > 0 and planet_rays <= kernel_rays // 10,
      "inertial: the loads took %d planet rays beside %d kernel rays" % (planet_rays, kernel_rays))
within_error_bars(art, hand, "inertial, 30°, default settings")

# 3. Tracking the Sun.
track = run("track", EXAMPLE + MONTE_CARLO)
angle = track["articulation/angle"][:, 0]
config = track["articulation/configuration"][:]
conf_angle = track["articulation/configuration_angle"][:, 0]
sun = track["orbit/sun_body"][:]
lit = track["orbit/sunlit_fraction"][:] > 0
check(np.allclose(angle / 10.0, np.round(angle / 10.0)), "tracking: angles are multiples of the 10° step")
# Front normal +z turned by θ about +y is (sin θ, 0, cos θ): the exact angle is atan2(s_x, s_z).
exact = np.degrees(np.arctan2(sun[:, 0], sun[:, 2]))
miss = np.abs((angle - exact + 180.0) % 360.0 - 180.0)
check(miss[lit].max() <= 5.0 + 1e-9, "tracking: an angle is %.3g° from the Sun's (step/2 = 5°)" % miss[lit].max())
first_lit = np.argmax(lit)
for p in range(len(angle)):
    if not lit[p]:
        previous = p - 1 if p > 0 else len(angle) - 1
        check(angle[p] == angle[previous], "tracking: position %d in eclipse does not hold the last angle" % p)
check(track["report"].attrs["eigendecompositions"] == 1, "tracking: one eigendecomposition")
# `radnet validate` counts the configurations the run makes (its memory estimate holds one
# network and GR per configuration): the same number, not one per step of the drive.
r = subprocess.run([RADNET, "validate", os.path.join(WORK, "track.yaml")], capture_output=True, text=True)
counted = re.search(r"; (\d+) configurations of the turning parts", r.stdout)
made = int(track["report"].attrs["articulation_configurations"])
check(r.returncode == 0 and counted is not None and int(counted.group(1)) == made,
      "tracking: validate counts %s configurations, the run made %d (%s)" %
      (counted.group(1) if counted else "no", made, r.stdout.strip()))
check(set(np.round(conf_angle[1:], 6)) | {0.0} >= set(np.round(angle, 6)), "tracking: every angle is a configuration's")
check(all(conf_angle[config[p]] == angle[p] for p in range(len(angle))), "tracking: positions in their configuration")
for k in sorted(set(config))[:2]:
    hand = run("track_hand_%d" % k, turned_by_hand(EXAMPLE, conf_angle[k]) + MONTE_CARLO)
    columns = np.where(config == k)[0]
    for key in LOADS:
        same(track[key][:], hand[key][:], "tracking, configuration %d (%g°), %s" % (k, conf_angle[k], key), columns=columns)
# `radnet export` of a position takes its configuration's GR.
turned_position = int(np.argmax(config > 0))
k = config[turned_position]
csv_dir = os.path.join(WORK, "export-%d" % turned_position)
r = subprocess.run([RADNET, "export", os.path.join(WORK, "track.h5"), "--format", "csv", "--position",
                    str(turned_position), "-o", csv_dir], capture_output=True, text=True)
check(r.returncode == 0, "export of a turned position: exit %d %s" % (r.returncode, r.stderr))
if r.returncode == 0:
    gr = track["articulation/configuration_%d/radiative_exchange" % k][:]
    written = {}
    for line in open(os.path.join(csv_dir, "conductors.csv")).read().splitlines()[1:]:
        kind, a, b, value = line.split(",")[:4]
        if kind == "GR" and b.isdigit() and int(b) < gr.shape[0]:
            written[(int(a), int(b))] = float(value)
    worst = max(abs(v - gr[a, b]) for (a, b), v in written.items()) / largest(gr)
    check(len(written) > 0 and worst <= 1e-9, "export of position %d: GR differs from configuration %d's by %.3g" %
          (turned_position, k, worst))
xmf = open(os.path.join(WORK, "track.xmf")).read()
for k in sorted(set(config)):
    if k > 0:
        check("/xdmf/vertices/configuration_%d<" % k in xmf, "XDMF: configuration %d's vertices are not used" % k)
        check("xdmf/vertices/configuration_%d" % k in track, "HDF5: configuration %d's vertices missing" % k)

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("articulation: all checks passed")
