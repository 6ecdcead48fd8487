#!/usr/bin/python3
"""The ground-truth quality benchmarks of detexture (bench/README.md).

    bench/quality [BUILD_DIR]       -> run the synthetic-shape suite, write bench/RESULTS.md (quality section)
    bench/quality_real [BUILD_DIR]  -> run the real-shape suite (--suite real), its own RESULTS.md section
    bench/tune_peers [BUILD_DIR]    -> grid-search the peers' parameters, write bench/peer_params.json
                                       (--suite real: bench/peer_params_real.json)

All are thin wrappers around this file; the two suites share every line of the
machinery and differ only by their Suite record (SUITES, below). Use Debian's /usr/bin/python3 (numpy is
not needed; every metric comes from `detexture compare --json`).

The suite, the detexture parameter rule, the peer grids and the tuning
criterion are all defined here, in one place, and documented in bench/README.md.
"""

import argparse
import concurrent.futures
import datetime
import hashlib
import itertools
import json
import math
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys
import time
from dataclasses import dataclass

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS_FILE = os.path.join(REPO, "bench", "RESULTS.md")
SPEED_BEGIN, SPEED_END = "<!-- speed:begin -->", "<!-- speed:end -->"
# Debian's assimp-testmodels: the real suite's base meshes are made from these
# at run time (nothing of the package is committed).
ASSIMP_MODELS = "/usr/share/assimp/models"

# --------------------------------------------------------------------------
# The suite. Fixed before any method was run on it (see bench/README.md);
# do not tune it to the results.
# --------------------------------------------------------------------------

POINTS = 100_000  # textured samples per case
GROUND_TRUTH_POINTS = 200_000  # `detexture synth` default
SEED = 1

# Area and bounding-box diagonal of each base shape (docs/synth_and_compare.md):
# the area gives the sampling density rho = N / area, which converts the
# peers' relative parameters into neighbour counts and MeshLab filter scales.
SHAPE_AREA = {
    "sphere": math.pi,  # 4 pi 0.5^2
    "cube": 6.0,
    "cylinder": 1.5 * math.pi,  # side 2 pi 0.5 * 1 + caps 2 pi 0.5^2
    "torus": 4 * math.pi**2 * 0.35 * 0.15,
    "pyramid": 1.0 + 2.0 * math.sqrt(1.25),  # base + 4 triangles of slant height sqrt(1.25)
    "plane": 1.0,
}
SHAPE_DIAGONAL = {
    "sphere": math.sqrt(3),
    "cube": math.sqrt(3),
    "cylinder": math.sqrt(3),
    "torus": math.sqrt(2 + 0.3**2),
    "pyramid": math.sqrt(3),
    "plane": math.sqrt(2),
}


# Area and diagonal of the base shapes not in the tables above (the real
# meshes, the organic shapes): read from `detexture synth`'s line "base area A
# diagonal D" when each case is synthesized (synthesize). The tables keep
# precedence for their shapes, so the synthetic suite's parameters do not move.
BASE_GEOMETRY = {}  # case name -> (area, diagonal)


@dataclass(frozen=True)
class RealMesh:
    """A base mesh made by bench/peers/prepare_mesh from a model of assimp-testmodels."""
    name: str
    model: str  # path under ASSIMP_MODELS
    components: str = "largest"  # prepare_mesh --components
    subdivide: int = 0  # prepare_mesh --subdivide (Loop levels)
    what: str = ""
    up: str = "y"  # the model's up axis, for the pictures (every model used is y-up)

    def path(self, work):
        return os.path.join(work, "meshes", self.name + ".ply")

    def prepare_args(self):
        return ["--components", self.components, "--subdivide", str(self.subdivide)]


@dataclass(frozen=True)
class Case:
    name: str
    shape: str  # a synth --shape, or "mesh" with `mesh` set
    texture: str
    layout: str
    size: float  # R: feature size (the largest one for multiscale), model units
    amplitude: float  # A, model units
    mixed_signs: bool = False
    noise: float = 0.0  # Gaussian noise std dev as a fraction of the base diagonal
    what: str = ""
    mesh: RealMesh = None  # the base mesh, for shape "mesh"
    points: int = POINTS  # textured samples

    def synth_args(self, points, mesh_path=None):
        base = ["--base-mesh", mesh_path] if self.mesh else ["--shape", self.shape]
        args = base + ["--texture", self.texture, "--layout", self.layout,
                       "--size", fmt(self.size), "--amplitude", fmt(self.amplitude),
                       "--points", str(points), "--ground-truth-points", str(GROUND_TRUTH_POINTS),
                       "--seed", str(SEED)]
        if self.mixed_signs:
            args.append("--mixed-signs")
        if self.noise > 0:
            args += ["--noise", fmt(self.noise)]
        return args

    def base(self):
        """(area, bounding-box diagonal) of the base surface."""
        if self.mesh is None and self.shape in SHAPE_AREA:
            return SHAPE_AREA[self.shape], SHAPE_DIAGONAL[self.shape]
        if self.name not in BASE_GEOMETRY:
            raise RuntimeError(f"{self.name}: the base area is not known before synthesis "
                               "(`detexture synth` prints it as 'base area A diagonal D')")
        return BASE_GEOMETRY[self.name]

    def density(self, points):
        """Points per unit area (of the base surface)."""
        return points / self.base()[0]

    def noise_sigma(self):
        return self.noise * self.base()[1]


SUITE = [
    Case("cube-bumps", "cube", "bumps", "sparse", 0.035, 0.012,
         what="sharp edges and corners; separated Gaussian bumps"),
    Case("cube-noisy", "cube", "bumps", "dense", 0.035, 0.012, mixed_signs=True, noise=0.001,
         what="sharp; touching bumps up and down; noise 0.001d (0.0017, 14% of A)"),
    Case("pyramid-vgrooves", "pyramid", "v-grooves", "sparse", 0.03, 0.01,
         what="sharp edges at 63 and 117 degrees, apex; parallel V grooves"),
    Case("sphere-multiscale", "sphere", "multiscale", "sparse", 0.036, 0.015, mixed_signs=True,
         what="the paper's Table 3 sphere: bumps of two scales (R, R/3), up and down"),
    Case("torus-waves", "torus", "waves", "dense", 0.02, 0.008,
         what="dense sinusoidal ridges on a doubly curved surface (saddle inside)"),
    Case("cylinder-scales", "cylinder", "scales", "dense", 0.035, 0.01,
         what="dense Voronoi scales (creases between cells); sharp rims"),
    Case("plane-domes", "plane", "domes", "sparse", 0.02, 0.008, mixed_signs=True,
         what="sparse domes and dimples with vertical rims; open border"),
    Case("cylinder-ugrooves-noisy", "cylinder", "u-grooves", "sparse", 0.03, 0.01, noise=0.0005,
         what="U grooves with vertical walls; noise 0.0005d (0.0009, 9% of A)"),
]

# --------------------------------------------------------------------------
# The real-shape suite (issue 9): textured real meshes and organic shapes.
# Fixed, and committed, before any method was run on it (bench/README.md);
# do not tune it to the results. R is chosen per case from the size of the
# shape's small parts (a leg's, a finger's, a wall's thickness, measured on
# the meshes by casting rays inward) and so that R >= 4 point spacings and the
# run fits its budget; nothing about any method's results entered the choice.
# --------------------------------------------------------------------------

REAL_MESHES = {
    m.name: m for m in [
        RealMesh("wuson", "PLY/Wuson.ply", "largest", 2,
                 "the Wuson bull (PLY): legs about 0.04 thick, horns and tail about 0.02"),
        RealMesh("human", "Collada/human.zae", "largest", 1,
                 "a standing person (COLLADA): arms about 0.05 thick, fingers about 0.01"),
        RealMesh("duck", "Collada/duck.dae", "largest", 2,
                 "the COLLADA duck: smooth and closed, no thin part"),
        RealMesh("spider", "OBJ/spider.obj", "all", 2,
                 "the spider (OBJ): 18 closed parts, legs 0.012-0.02 thick that pierce the body"),
        RealMesh("engine", "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "largest", 0,
                 "the block of the glTF 2CylinderEngine: a CAD casting, flat faces, sharp "
                 "edges, bores, walls about 0.03 thick"),
    ]
}

REAL_SUITE = [
    Case("wuson-scales", "mesh", "scales", "dense", 0.015, 0.005, mesh=REAL_MESHES["wuson"],
         what="an animal covered in scales: thin legs, horns and a tail; r = 0.0225 about half a leg"),
    Case("human-bumps", "mesh", "bumps", "sparse", 0.012, 0.004, mixed_signs=True,
         mesh=REAL_MESHES["human"],
         what="a person with bumps up and down; fingers (0.01) thinner than r = 0.018"),
    Case("duck-multiscale", "mesh", "multiscale", "sparse", 0.03, 0.012, mixed_signs=True,
         mesh=REAL_MESHES["duck"],
         what="a smooth closed character; bumps of two scales (R, R/3) up and down"),
    Case("spider-bumps", "mesh", "bumps", "dense", 0.012, 0.004, mesh=REAL_MESHES["spider"],
         what="an animal with thin legs; touching bumps as wide as a leg"),
    Case("engine-vgrooves-noisy", "mesh", "v-grooves", "sparse", 0.03, 0.01, noise=0.0005,
         mesh=REAL_MESHES["engine"], points=150_000,
         what="a thin-walled CAD part: V grooves, sharp edges, walls (0.03) thinner than r = 0.045; "
              "noise 0.0005d; 150,000 points so that R is 4.5 point spacings"),
    Case("blob-bumps", "blob", "bumps", "sparse", 0.02, 0.007,
         what="a smooth body with six limbs of varying width; separated bumps"),
    Case("disc-domes", "disc", "domes", "sparse", 0.02, 0.007, mixed_signs=True,
         what="a thin disc (two sheets 0.06 apart, a rim of radius 0.03 = r); domes and dimples"),
    Case("knot-waves", "knot", "waves", "dense", 0.02, 0.006,
         what="a knotted tube of radius 0.07 (sag of r = 0.03 is 0.0064, 4 times λ); dense ridges"),
    Case("ellipsoid-bumps-noisy", "ellipsoid", "bumps", "dense", 0.02, 0.007, mixed_signs=True,
         noise=0.0008,
         what="curvature varying from radius 0.08 at the tips to 1.25; touching bumps up and down; "
              "noise 0.0008d (0.001, 14% of A)"),
    Case("saddle-scales", "saddle", "scales", "sparse", 0.015, 0.005,
         what="negative Gaussian curvature, open border; separated scales"),
]

# --------------------------------------------------------------------------
# detexture: one parameter rule for every case (bench/README.md).
# --------------------------------------------------------------------------

RADIUS_FACTOR = 1.5  # r = 1.5 R
NOISE_LAMBDA_FACTOR = 3.0  # lambda = max(default 0.05 r, 3 sigma_noise)
DEFAULT_LAMBDA_OF_R = 0.05  # detexture's default lambda = 0.05r (since 6357b08)


def detexture_rule(case):
    """Parameters a user would pick from the texture scale (and noise level).

    sigma_s = r is detexture's default; it is written out so the rule does not
    drift with the defaults."""
    r = RADIUS_FACTOR * case.size
    args = ["-r", fmt(r), "--sigma-s", fmt(r)]
    lam = NOISE_LAMBDA_FACTOR * case.noise_sigma()
    if lam > DEFAULT_LAMBDA_OF_R * r:
        args += ["--lambda", fmt(lam)]
    return args


DETEXTURE_VARIANTS = [
    # name, extra options, what it shows
    ("detexture", [], "the full method (defaults)"),
    ("no-subneighborhood", ["--no-subneighborhood"], "plain Gaussian over R_i (Fig. 4 ablation)"),
    ("patch-shift", ["--guidance", "patch-shift"],
     "the paper's patch-shift guidance, Eqs. 4-8 (the default until plain guidance, the "
     "paper's Fig. 7 ablation, replaced it)"),
    ("update-eq9", ["--update", "eq9"], "position update of Eq. 9, no isotropic neighbourhood (Fig. 8)"),
    ("hard-subneighborhood", ["--subneighborhood", "hard", "--vote-normal-angle", "180"],
     "the paper's Ω_i: hard labels from positions-only votes (the default before e5f3331)"),
    ("whole-neighborhoods", ["--thin-part-radius", "1"],
     "R_i of radius r everywhere, also on parts thinner than r (before 222f0d4)"),
    ("flat-shared", ["--surface", "plane", "--sheet-angle", "180", "--move-limit", "0",
                     "--subneighborhood", "hard", "--vote-normal-angle", "180",
                     "--thin-part-radius", "1", "--guidance", "patch-shift",
                     "--surface-split-angle", "180", "--output-normals", "filtered",
                     "--counter-move-limit", "0", "--tip-depth", "0", "--keep-cells-tops"],
     "the paper's plane test in Eq. 2 and R_i across sheets, no move limit (before issue 9)"),
    ("full-anchors", ["--anchor-height", "0", "--anchor-angle", "0"],
     "every surface point held fully at its place by the global update, also when noisy or on "
     "a wave's flank (before session 6)"),
    ("no-anchor-angle", ["--anchor-angle", "0"],
     "surface points held at their place whatever the tilt of their input normal against the "
     "filtered one (the default before session 12)"),
    ("no-surface-split", ["--surface-split-angle", "180"],
     "R_i not split after texture detection: points past a tip or a rim stay in each other's "
     "R_i unless back to back (before session 8)"),
    ("no-blend-coherence", ["--blend-coherence", "0"],
     "output normals blended by the mean angle alone, without the isotropic path "
     "(fit_normals_to_positions.h; the default before session 12's second change)"),
    ("no-wave-release", ["--wave-share-low", "1"],
     "no second update where waves stayed in the positions: their crests and troughs, "
     "labelled surface, keep their anchors (remove_texture.h; the default before session 14)"),
    ("wave-rest-held", ["--wave-rest-anchor", "1"],
     "the second update over waves lowers the anchors of the flagged points alone: the flanks "
     "and crests beside them stay held at their input heights (remove_texture.h; the default "
     "before session 38)"),
    ("wave-unceiled", ["--wave-ceiling", "0"],
     "the second update over waves without the ceiling: crests in the upper half of their "
     "relief may move outward (troughs inward) by more than λ (limit_tip_moves.h; the default "
     "before session 39)"),
    ("update-filtered", ["--update-filtered-normals"],
     "the position update fits the filtered normals everywhere, also at facets whose exact "
     "input normal the filters rounded and the output would keep (remove_texture.h, "
     "update_input_normals; the default before session 43)"),
    ("blend-everywhere", ["--blend-share-high", "0"],
     "output normals blended with the narrow window (1-2°) on every cloud, also where no "
     "waves are left (fit_normals_to_positions.h; the default before session 15)"),
    ("one-scale-fit", ["--fit-fine-ratio", "0"],
     "output normals fitted at one scale (σ = 0.3 r) only, without the fine fit where it "
     "departs by more than its noise explains (fit_normals_to_positions.h; the default "
     "before session 17)"),
    ("no-kept-input", ["--keep-input-high", "0", "--keep-input-exact-angle", "0",
                       "--keep-input-still-angle", "0"],
     "no input normals kept, neither where nothing near the point moved nor exact ones: the "
     "fit and its blend everywhere (keep_input_normals.h; the default before session 18)"),
    ("no-exact-input", ["--keep-input-exact-angle", "0", "--keep-input-still-angle", "0"],
     "exact (noise-free) input normals not kept where the points moved, neither within 4° of "
     "the fitted ones nor up to 20° where the surface stayed (keep_input_normals.h; the "
     "default before session 21)"),
    ("no-still-input", ["--keep-input-still-angle", "0", "--keep-input-facet-neighbors", "0",
                        "--keep-input-surface-only"],
     "exact input normals kept within 4° of the fitted ones only, not up to 20° where nothing "
     "within the solve radius moved by more than λ and they are a facet's "
     "(keep_input_normals.h; the default before session 23)"),
    ("no-facet-input", ["--keep-input-facet-neighbors", "0", "--keep-input-still-reach", "0",
                        "--keep-input-still-any-move", "--keep-input-surface-only"],
     "exact input normals read from their 8 nearest neighbors as one plane only, not also "
     "from their facet among 24 past its edges (keep_input_normals.h; the default before "
     "session 24)"),
    ("no-reach-input", ["--keep-input-still-reach", "0", "--keep-input-still-any-move",
                        "--keep-input-surface-only"],
     "where the surface stayed, exact input normals taken where the fitted normals within the "
     "solve radius turn as much in any direction (the cone), not where they reach towards the "
     "input normal, and only where no point within it moved by more than λ, not also where "
     "none of the point's facet did; and only at surface points (keep_input_normals.h; the "
     "default before session 25)"),
    ("surface-only-input", ["--keep-input-surface-only"],
     "exact input normals taken at surface points only, not also at texture-labelled points "
     "whose nearest neighbors' input normals agree (keep_input_normals.h; session 25's reach "
     "and facet move without its third change)"),
    ("facet-members-8", ["--keep-input-facet-members", "8"],
     "a facet found past its edges needs 8 members among the 24 nearest, not 4: small "
     "facets of low-poly models keep the fitted normal (keep_input_normals.h; the default "
     "before session 28)"),
    ("facet-groups-0", ["--keep-input-facet-groups", "0"],
     "a facet found past its edges allows at most 2 neighbors whose input normals turn by "
     "1-3°, even where they all lie on one other facet: points beside the shallow edges of "
     "low-poly models keep the fitted normal (keep_input_normals.h; the default before "
     "session 36)"),
    ("reached-0", ["--keep-input-reached-angle", "0"],
     "exact input normals that no other test took are not taken where the output normals "
     "around reach them: the facets of thin parts the fit rounded keep the fitted normal "
     "(keep_input_normals.h; the default before session 37)"),
    ("filtered-range", ["--fit-range-normals", "filtered"],
     "the output-normal fit's range weights read from the filtered normals instead of the "
     "input's (fit_normals_to_positions.h; the default before session 18)"),
    ("no-counter-limit", ["--counter-move-limit", "0"],
     "no limit on moves against the relief: points at concave junctions carried outward past "
     "raised relief by the rounded normals (limit_counter_moves.h; the default before session "
     "19)"),
    ("counter-session26", ["--counter-move-limit", "0.25", "--counter-move-limit-released",
                           "--counter-move-released-lean", "0.35"],
     "moves against raised relief saturated at a quarter of the texture height instead of an "
     "eighth, and in the second update over waves the released points limited too, from the "
     "first pass's lean (limit_counter_moves.h; the default before session 27)"),
    ("no-tip-limit", ["--tip-depth", "0"],
     "the tops and bottoms of the relief free to end past their neighbors: groove floors "
     "carried deeper and crests further out by the rounded normals (limit_tip_moves.h; the "
     "default before session 26)"),
    ("no-sink-limit", ["--sink-slack", "0"],
     "points that raised relief rises above free to sink deeper than the texture height and "
     "their own height above their fitted surface: junction points carried inward by the "
     "rounded normals (limit_sink_moves.h; the default before session 35)"),
    ("counter-hard", ["--counter-move-hard"],
     "moves against the relief cut at the limit instead of saturated smoothly "
     "(limit_counter_moves.h; the default in session 19)"),
    ("no-counter-engraved", ["--counter-move-engraved-share", "0", "--keep-cells-tops"],
     "inward moves never limited where the relief leans engraved, even where the texture is "
     "sparse (grooves; limit_counter_moves.h; the default in session 19)"),
    ("counter-engraved-all", ["--counter-move-engraved-share", "1"],
     "inward moves limited wherever the relief leans engraved, dense scales too "
     "(limit_counter_moves.h; an option)"),
    ("cells-tops", ["--keep-cells-tops"],
     "the output left on the tops of dense raised cells (scales packed edge to edge), whose "
     "gaps the update lifted, instead of lowered to the cells' feet (lower_raised_cells.h; "
     "the default before session 31)"),
    ("cells-unlimited", ["--cells-max-depth", "0", "--cells-max-turn", "180"],
     "dense raised cells lowered by the whole spread of their feet, even where that takes a "
     "point more than 1.25 texture heights below its own input, and along its own output "
     "normal even where it turned over against its neighbors' (lower_raised_cells.h; the "
     "default before session 34)"),
    ("cells-any-turn", ["--cells-max-turn", "180"],
     "dense raised cells: points whose output normal turned over against their neighbors' sink "
     "along it too, not along the neighbors' mean (lower_raised_cells.h; the depth limit kept)"),
    ("still-move-1", ["--keep-input-still-move", "1"],
     "an exact input normal is kept where the surface stayed only if nothing within 0.5 r "
     "moved by more than λ, not 3 λ, on every relief (keep_input_normals.h; the default "
     "before session 32, which keeps λ only where the relief reads as sparse engraving)"),
    ("fitted-normals", ["--output-normals", "fitted"],
     "output normals fitted to the output positions everywhere, without the blend "
     "(fit_normals_to_positions.h; an option)"),
    ("filtered-normals", ["--output-normals", "filtered"],
     "the filtered normals as output normals, as the paper (the default before session 9)"),
    ("sigma-r-30", ["--sigma-r", "30", "--move-limit", "1.5"],
     "σr 30° and the move limit at 1.5 × the texture height (the defaults before session 9)"),
    ("estimated-normals", ["--ignore-normals"],
     "the input's normals dropped and estimated from the positions (PCA, 16 neighbours), as "
     "for a scan without normals or with unreliable ones; the input row's normals are exact, "
     "noise-free even on the noisy cases"),
    ("auto", None, "the full method with no parameters at all: r from estimate_texture_scale (issue 10)"),
]

# --------------------------------------------------------------------------
# Peers: grids of parameters relative to the feature size R (bench/README.md).
# --------------------------------------------------------------------------

PEER_GRIDS = {
    # K nearest neighbours chosen so that their radius is about c R:
    # K = rho pi (c R)^2 (CGAL sets its spatial bandwidth from the K-NN distance).
    "cgal-bilateral": {"c": [1.0, 1.5, 2.0], "sharpness": [15, 30, 60], "iterations": [1, 3]},
    # radius c R (detexture's radius neighbourhoods, query point first), jet degree.
    "cgal-jet": {"c": [1.0, 1.5, 2.0, 3.0], "degree": [2, 3]},
    # radius c R, Gaussian weight exp(-d^2 / (c R)^2) (PCL's default), polynomial order.
    "pcl-mls": {"c": [1.0, 1.5, 2.0, 3.0], "order": [1, 2, 3]},
    # kernel support about c R: FILTER_SCALE = c R sqrt(pi rho) / 2, since MeshLab's
    # per-point radius is about 2 / sqrt(pi rho) (2 sqrt(d16^2 / 16) from 16 neighbours).
    "meshlab-rimls": {"c": [1.0, 1.5, 2.0, 3.0], "sigma_n": [0.5, 1.0, 2.0]},
}
PEER_ORDER = ["cgal-bilateral", "cgal-jet", "pcl-mls", "meshlab-rimls"]
# The real suite's grids: smaller (tuning there is time-boxed to 25 minutes),
# centred on what won on the synthetic suite, and with WLOP.
REAL_PEER_GRIDS = {
    "cgal-bilateral": {"c": [1.5, 2.0, 3.0], "sharpness": [30, 60], "iterations": [3]},
    "cgal-jet": {"c": [1.5, 2.0, 3.0], "degree": [2]},
    "pcl-mls": {"c": [1.5, 2.0, 3.0], "order": [1, 2]},
    "meshlab-rimls": {"c": [2.0, 3.0, 4.0], "sigma_n": [0.5, 1.0]},
    # neighbor_radius c R; normals from the K = rho pi (c R / 2)^2 nearest output points.
    "cgal-wlop": {"c": [1.0, 1.5, 2.0]},
}
REAL_PEER_ORDER = PEER_ORDER + ["cgal-wlop"]
PEER_LABEL = {
    "cgal-bilateral": "CGAL bilateral (EAR)",
    "cgal-jet": "CGAL jet",
    "pcl-mls": "PCL MLS",
    "meshlab-rimls": "MeshLab RIMLS",
    "cgal-wlop": "CGAL WLOP",
}
TUNE_POINTS = 40_000
# WLOP iterations: not tuned. Its metrics hardly move with them (bumpy sphere,
# 100,000 points, R = 0.036, radius R: residual texture 0.001565 after 3
# iterations, 0.001543 after 5, 0.001514 after 10, 0.001498 after 20; CGAL's
# default is 35) while the time is linear in them (bench/README.md).
WLOP_ITERATIONS = 5


def peer_program(build, peer):
    if peer == "meshlab-rimls":
        if not shutil.which("meshlabserver"):
            return None
        return os.path.join(REPO, "bench", "peers", "peer_meshlab_rimls.sh")
    name = {"cgal-bilateral": "peer_cgal_bilateral", "cgal-jet": "peer_cgal_jet",
            "pcl-mls": "peer_pcl_mls", "cgal-wlop": "peer_cgal_wlop"}[peer]
    path = os.path.join(build, "bench", "peers", name)
    return path if os.access(path, os.X_OK) else None


# MeshLab 2020.09 never computes the mean point spacing its RIMLS projection
# multiplies PROJECTION_ACCURACY by, so the stop test never passes and every
# point takes all MAX_PROJECTION_ITERS steps (MeshLab's default 15; the output is
# bit-identical for accuracies 1e-4 and 1e-2). After 4 steps 99.6% of the points
# are within 1e-6 of their 15-step position and every metric of every case is
# within 0.08% of the 15-step one (bench/README.md, Budget), at about a third of
# the time. Not a quality parameter: the tuned ones are in bench/peer_params.json.
RIMLS_PROJECTION_ITERS = 4
RIMLS_REFITTING_ITERS = 3  # MeshLab's default, written out because it comes first


def peer_args(peer, params, case, points, threads=None):
    """Command-line arguments (after IN OUT) of a peer for relative params on a case."""
    R = case.size
    rho = case.density(points)
    c = params["c"]
    t = [] if threads is None else ["-t", str(threads)]
    if peer == "cgal-bilateral":
        k = max(8, round(rho * math.pi * (c * R) ** 2))
        return ["-k", str(k), "-s", fmt(params["sharpness"]), "-i", str(params["iterations"])] + t
    if peer == "cgal-jet":
        return ["-r", fmt(c * R), "-d", str(params["degree"])] + t
    if peer == "pcl-mls":
        return ["-r", fmt(c * R), "-o", str(params["order"])] + t
    if peer == "meshlab-rimls":
        scale = c * R * math.sqrt(math.pi * rho) / 2
        return [fmt(scale), fmt(params["sigma_n"]), str(RIMLS_REFITTING_ITERS),
                str(RIMLS_PROJECTION_ITERS)]
    if peer == "cgal-wlop":
        k = max(24, round(rho * math.pi * (c * R / 2) ** 2))
        return ["-r", fmt(c * R), "-i", str(WLOP_ITERATIONS), "-k", str(k)] + t
    raise ValueError(peer)


# --------------------------------------------------------------------------
# Running things
# --------------------------------------------------------------------------


# Single-thread seconds per unit of rho R^2 (which sets every method's
# neighbourhood size) on this machine, measured; used only to start the longest
# runs first, so they need not be exact.
RUN_COST = {
    "detexture": 0.15, "no-subneighborhood": 0.15, "patch-shift": 0.15, "update-eq9": 0.6,
    "hard-subneighborhood": 0.15, "whole-neighborhoods": 0.15, "flat-shared": 0.15, "auto": 0.15,
    "full-anchors": 0.15, "fitted-normals": 0.15, "filtered-normals": 0.15, "sigma-r-30": 0.15,
    "estimated-normals": 0.15, "no-anchor-angle": 0.15, "no-blend-coherence": 0.15,
    "no-wave-release": 0.15, "blend-everywhere": 0.15, "one-scale-fit": 0.15,
    "cgal-bilateral": 0.8, "cgal-jet": 1.0, "pcl-mls": 0.05, "meshlab-rimls": 0.5, "cgal-wlop": 1.2,
}


def estimated_seconds(method, case):
    return RUN_COST.get(method, 1.0) * case.density(case.points) * case.size ** 2 * case.points / POINTS


# --------------------------------------------------------------------------
# The two suites: everything that differs between them.
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Suite:
    name: str  # --suite value
    command: str  # wrapper, for the RESULTS.md header
    title: str  # RESULTS.md section heading
    cases: list
    peers: list
    grids: dict
    peer_params_file: str
    notes_file: str  # hand-written reading, copied into the section when present
    begin: str  # RESULTS.md markers
    end: str
    work: str  # default work folder under BUILD_DIR
    tune_work: str


SUITES = {
    "quality": Suite("quality", "bench/quality", "Quality against ground truth (`bench/quality`)",
                     SUITE, PEER_ORDER, PEER_GRIDS, os.path.join(REPO, "bench", "peer_params.json"),
                     os.path.join(REPO, "bench", "quality_notes.md"),
                     "<!-- quality:begin -->", "<!-- quality:end -->", "bench-quality", "bench-tune"),
    "real": Suite("real", "bench/quality_real",
                  "Quality on real shapes against ground truth (`bench/quality_real`)",
                  REAL_SUITE, REAL_PEER_ORDER, REAL_PEER_GRIDS,
                  os.path.join(REPO, "bench", "peer_params_real.json"),
                  os.path.join(REPO, "bench", "quality_real_notes.md"),
                  "<!-- quality-real:begin -->", "<!-- quality-real:end -->", "bench-real",
                  "bench-tune-real"),
}


def fmt(x):
    return f"{x:.6g}"


def log(msg):
    print(msg, flush=True)


def run(cmd, log_path, timeout):
    """Run cmd, stdout+stderr to log_path; return (ok, stdout text, message)."""
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired as e:
        with open(log_path, "w") as f:
            f.write("$ " + shlex.join(cmd) + f"\nTIMEOUT after {timeout} s\n")
        return False, "", f"timeout after {timeout:.0f} s"
    wall = time.monotonic() - t0
    with open(log_path, "w") as f:
        f.write("$ " + shlex.join(cmd) + "\n" + p.stdout + p.stderr + f"\n# wall {wall:.2f} s\n")
    if p.returncode != 0:
        last = (p.stderr.strip().splitlines() or ["?"])[-1]
        return False, p.stdout, f"exit {p.returncode}: {last}"
    return True, p.stdout, ""


def last_seconds(stdout):
    lines = [l for l in stdout.strip().splitlines() if l.strip()]
    if lines:
        m = re.match(r"seconds:\s*([0-9.eE+-]+)", lines[-1].strip())
        if m:
            return float(m.group(1))
    return None


def detexture_seconds(stats_path):
    """Algorithm time from --stats: total minus reading and writing."""
    with open(stats_path) as f:
        s = json.load(f)["seconds"]
    return s["total"] - s.get("read", 0.0) - s.get("write", 0.0)


def made_by(cmd, outputs):
    """Whether `outputs` exist and were made by exactly this command and program
    (the key prepare_mesh and synthesize store next to their output)."""
    key = outputs[0] + ".key.json"
    if not all(os.path.exists(o) for o in outputs) or not os.path.exists(key):
        return False
    with open(key) as f:
        return json.load(f) == {"command": cmd[1:], "program": file_digest(cmd[0])}


def store_made_by(cmd, outputs):
    with open(outputs[0] + ".key.json", "w") as f:
        json.dump({"command": cmd[1:], "program": file_digest(cmd[0])}, f, indent=1)


def prepare_mesh(build, mesh, work):
    """The base mesh made by bench/peers/prepare_mesh (reused when made by the same command)."""
    out = mesh.path(work)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    model = os.path.join(ASSIMP_MODELS, mesh.model)
    if not os.path.exists(model):
        raise RuntimeError(f"{model} is missing: install assimp-testmodels (scripts/install_peer_deps.sh)")
    program = os.path.join(build, "bench", "peers", "prepare_mesh")
    if not os.access(program, os.X_OK):
        raise RuntimeError(f"{program} is not built (it needs CGAL and libassimp-dev)")
    cmd = [program, model, out] + mesh.prepare_args()
    if not made_by(cmd, [out]):
        ok, _, msg = run(cmd, out[:-4] + ".prepare.log", 300)
        if not ok:
            raise RuntimeError(f"prepare_mesh failed for {mesh.name}: {msg}")
        store_made_by(cmd, [out])
    return out


def synthesize(build, case, points, work):
    """The case's cloud, in Morton order (see morton_order), and its ground truth.

    Reused when present and made by the same command and the same detexture
    binary (so a rebuilt synth never leaves stale clouds; a rerun costs seconds,
    and the peers' cache keys on the cloud's content, not its date); records
    the base area and diagonal that synth prints (BASE_GEOMETRY)."""
    base = os.path.join(work, case.name)
    ply, gt, ordered = base + ".ply", base + ".gt.ply", base + ".morton.ply"
    mesh_path = prepare_mesh(build, case.mesh, work) if case.mesh else None
    cmd = [detexture_bin(build), "synth", "-o", ply] + case.synth_args(points, mesh_path)
    log_path = base + ".synth.log"
    fresh = made_by(cmd, [ply, gt]) and (mesh_path is None
                                         or os.path.getmtime(mesh_path) <= os.path.getmtime(ply))
    if not fresh:
        ok, _, msg = run(cmd, log_path, 300)
        if not ok:
            raise RuntimeError(f"synth failed for {case.name}: {msg}")
        store_made_by(cmd, [ply, gt])
    with open(log_path) as f:
        m = re.search(r"base area ([0-9.eE+-]+) diagonal ([0-9.eE+-]+)", f.read())
    if m:
        BASE_GEOMETRY[case.name] = (float(m.group(1)), float(m.group(2)))
    case.base()  # fails here, with a message, when the area is needed and synth did not give it
    if not os.path.exists(ordered) or os.path.getmtime(ordered) < os.path.getmtime(ply):
        morton_order(ply, ordered)
    return ordered, gt


PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
             "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
             "float": "f", "float32": "f", "double": "d", "float64": "d"}


def morton_order(src, dst):
    """Write the points of src (a binary little-endian PLY of vertices only, as
    `detexture synth` writes) to dst sorted along a Morton (Z-order) curve.

    The same points, only reordered: every metric is unchanged (checked: identical
    metrics for detexture and CGAL bilateral), but `detexture synth` emits its
    points in random order, the worst case for the k-d trees of the peers, which,
    unlike detexture, do not reorder their input: CGAL bilateral needs about half
    the CPU time on the ordered cloud (bench/README.md, Budget). Every method reads
    this same file."""
    with open(src, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise RuntimeError(f"{src}: expected a binary little-endian PLY")
    elements = [l.split() for l in header if l.startswith("element ")]
    if len(elements) != 1 or elements[0][1] != "vertex":
        raise RuntimeError(f"{src}: expected vertices only")
    n = int(elements[0][2])
    offsets, size = {}, 0
    for l in header:
        if l.startswith("property "):
            t, name = l.split()[1:3]
            if t == "list" or t not in PLY_TYPES:
                raise RuntimeError(f"{src}: unsupported property '{l}'")
            offsets[name] = (size, "<" + PLY_TYPES[t])
            size += struct.calcsize(PLY_TYPES[t])
    if len(data) != end + n * size:
        raise RuntimeError(f"{src}: size does not match its header")
    xyz = [[struct.unpack_from(offsets[c][1], data, end + i * size + offsets[c][0])[0] for i in range(n)]
           for c in "xyz"]
    lo = [min(v) for v in xyz]
    extent = max(max(v) - l for v, l in zip(xyz, lo)) or 1.0
    spread = [0] * 1024  # bit i of a 10-bit cell index goes to bit 3i
    for k in range(1024):
        spread[k] = sum(((k >> b) & 1) << (3 * b) for b in range(10))
    cell = [[min(1023, int((v[i] - l) / extent * 1024)) for i in range(n)] for v, l in zip(xyz, lo)]
    code = [spread[cell[0][i]] | spread[cell[1][i]] << 1 | spread[cell[2][i]] << 2 for i in range(n)]
    order = sorted(range(n), key=lambda i: (code[i], i))
    head = header[:2] + ["comment points sorted along a Morton curve by bench/quality_suite.py"] + header[2:]
    with open(dst + ".tmp", "wb") as f:
        f.write(("\n".join(head) + "\n").encode("ascii"))
        f.write(b"".join(data[end + i * size:end + (i + 1) * size] for i in order))
    os.replace(dst + ".tmp", dst)


def compare(build, result, gt):
    p = subprocess.run([detexture_bin(build), "compare", result, gt, "--json"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"compare {result} failed: {p.stderr.strip()}")
    return json.loads(p.stdout)


def detexture_bin(build):
    return os.path.join(build, "detexture")


def ensure_built(build, allow_build, suite=None):
    """Bring detexture in `build` up to date with the source (a no-op when it is),
    and build the peers (and the suite's other bench programs) when they are missing.

    The peers are not rebuilt when present: they relink whenever detexture's
    library changes, which would needlessly invalidate their cached outputs
    (their algorithms come from CGAL, PCL and MeshLab, not from src/)."""
    if not allow_build:
        if not os.access(detexture_bin(build), os.X_OK):
            sys.exit(f"error: {detexture_bin(build)} is missing; build it (bench/README.md) or drop --no-build")
        return
    cache = os.path.join(build, "CMakeCache.txt")
    if not os.path.exists(cache):
        log(f"configuring {build} (Release, with the peers) ...")
        subprocess.run(["cmake", "-S", REPO, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                        "-DDETEXTURE_BUILD_PEERS=ON"], check=True)
    with open(cache) as f:
        peers_configured = "DETEXTURE_BUILD_PEERS:BOOL=ON" in f.read()
    targets = ["detexture"]
    if peers_configured:
        if not os.path.isdir(os.path.join(build, "bench", "peers")) or not any(
                peer_program(build, p) for p in ("cgal-bilateral", "cgal-jet", "pcl-mls")):
            targets.append("peers")
        elif suite is not None and suite.name == "real":
            # Added after the first peers: build just those, so the others (and
            # their cached outputs) stay as they are.
            for program in ("peer_cgal_wlop", "prepare_mesh"):
                if not os.access(os.path.join(build, "bench", "peers", program), os.X_OK):
                    targets.append(program)
    else:
        log(f"note: {build} was configured without -DDETEXTURE_BUILD_PEERS=ON; "
            "the compiled peers will be skipped (reconfigure to include them)")
    log(f"building {' '.join(targets)} in {build} (-j2) ...")
    subprocess.run(["cmake", "--build", build, "-j2", "--target"] + targets, check=True,
                   stdout=subprocess.DEVNULL)


# --------------------------------------------------------------------------
# Tuning the peers
# --------------------------------------------------------------------------


def grid_points(grid):
    keys = list(grid)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]


def params_label(peer, params):
    return ", ".join(f"{k}={v}" for k, v in params.items())


def rank(values):
    """Ranks (1 = smallest) with ties sharing their mean rank; None ranks last."""
    order = sorted(range(len(values)), key=lambda i: (values[i] is None, values[i] if values[i] is not None else 0))
    ranks = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return ranks


def tune_points(case, points):
    """Points of a case when tuning: `points` for a case of the default size, in
    proportion for a larger one (the density, and so every peer's neighbour
    counts, keep the same ratio to the full run)."""
    return round(points * case.points / POINTS)


def tune(args):
    suite = SUITES[args.suite]
    build = os.path.abspath(args.build)
    ensure_built(build, not args.no_build, suite)
    work = os.path.abspath(args.work or os.path.join(build, suite.tune_work))
    os.makedirs(work, exist_ok=True)
    t_start = time.monotonic()
    cases = suite.cases
    log(f"tuning peers on the {suite.name} suite: {len(cases)} cases x {args.points} points in {work}")
    inputs = {c.name: synthesize(build, c, tune_points(c, args.points), work) for c in cases}
    peers = [p for p in suite.peers if (not args.peers or p in args.peers.split(","))]
    result = {}
    if os.path.exists(suite.peer_params_file):
        with open(suite.peer_params_file) as f:
            result = json.load(f)
    result.setdefault("peers", {})

    for peer in peers:
        prog = peer_program(build, peer)
        if prog is None:
            log(f"{peer}: not built / not installed, skipped")
            continue
        grid = grid_points(suite.grids[peer])
        jobs = []
        for gi, params in enumerate(grid):
            for c in cases:
                jobs.append((gi, params, c))

        def one(job):
            gi, params, c = job
            ply, gt = inputs[c.name]
            out = os.path.join(work, f"{c.name}.{peer}.{gi}.ply")
            cmd = [prog, ply, out] + peer_args(peer, params, c, tune_points(c, args.points), threads=1)
            ok, stdout, msg = run(cmd, out[:-4] + ".log", args.timeout)
            if not ok:
                return gi, c.name, None, msg
            m = compare(build, out, gt)
            m["seconds"] = last_seconds(stdout)
            os.remove(out)
            return gi, c.name, m, ""

        log(f"{peer}: {len(grid)} settings x {len(cases)} cases ({args.jobs} at a time, 1 thread each)")
        t_peer = time.monotonic()
        metrics = {}
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            for gi, cname, m, msg in pool.map(one, jobs):
                metrics[(gi, cname)] = m
                if m is None:
                    log(f"  {peer} [{params_label(peer, grid[gi])}] {cname}: FAILED {msg}")
        # Criterion: mean over cases of the rank (within this peer's grid) of the
        # residual texture (signed std) and of the mean normal error.
        scores = [0.0] * len(grid)
        for c in cases:
            res = [metrics[(gi, c.name)]["signed_std"] if metrics[(gi, c.name)] else None
                   for gi in range(len(grid))]
            ang = [metrics[(gi, c.name)]["normal_angle_mean_degrees"] if metrics[(gi, c.name)] else None
                   for gi in range(len(grid))]
            for gi, (a, b) in enumerate(zip(rank(res), rank(ang))):
                scores[gi] += (a + b) / 2 / len(cases)
        best = min(range(len(grid)), key=lambda gi: scores[gi])
        table = []
        for gi, params in enumerate(grid):
            row = {"params": params, "mean_rank": round(scores[gi], 3), "per_case": {}}
            for c in cases:
                m = metrics[(gi, c.name)]
                row["per_case"][c.name] = None if m is None else {
                    "signed_std": m["signed_std"], "normal_angle": m["normal_angle_mean_degrees"],
                    "dmean": m["dmean"], "seconds": m["seconds"]}
            table.append(row)
        result["peers"][peer] = {"params": grid[best], "mean_rank": round(scores[best], 3),
                                 "grid": suite.grids[peer], "date": datetime.date.today().isoformat(),
                                 "command": "bench/tune_peers " + " ".join(sys.argv[2:]),
                                 "seconds": round(time.monotonic() - t_peer),
                                 "results": table}
        log(f"{peer}: best {params_label(peer, grid[best])} (mean rank {scores[best]:.2f} of {len(grid)})")
        for gi in sorted(range(len(grid)), key=lambda gi: scores[gi])[:5]:
            log(f"    {scores[gi]:6.2f}  {params_label(peer, grid[gi])}")
        save_tuning(result, args, suite)  # after every peer, so a crash loses at most one
    log(f"done in {time.monotonic() - t_start:.0f} s")


def save_tuning(result, args, suite):
    result["criterion"] = ("for each case, rank the grid's settings by residual texture (signed std of "
                           "the distance to the ground truth) and by mean normal error; a setting's score "
                           "is the mean over cases of the average of its two ranks; lowest score wins")
    result["tuned_points"] = args.points
    result["suite"] = [c.name for c in suite.cases]
    with open(suite.peer_params_file, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    log(f"wrote {suite.peer_params_file}")


# --------------------------------------------------------------------------
# The benchmark
# --------------------------------------------------------------------------

METRIC_COLUMNS = [
    # header, key, format
    ("Dmean", "dmean", "{:.5f}"),
    ("Dmax", "dmax", "{:.4f}"),
    ("σ", "dstd", "{:.5f}"),
    ("residual texture", "signed_std", "{:.5f}"),
    ("normal error °", "normal_angle_mean_degrees", "{:.2f}"),
    ("% ≤ 10°", "normals_within_10_degrees_percent", "{:.1f}"),
    ("coverage mean", "coverage_mean", "{:.5f}"),
]


def machine_description():
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{os.cpu_count()} cores (nproc {os.cpu_count()}), {cpu}"


def git_revision():
    try:
        rev = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "--untracked-files=no",
                                "src", "include", "app"],
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
        return rev + (" (src/include/app modified)" if dirty else "")
    except OSError:
        return "unknown"


def load_peer_params(suite):
    if not os.path.exists(suite.peer_params_file):
        return {}
    with open(suite.peer_params_file) as f:
        return json.load(f).get("peers", {})


def quality(args):
    suite = SUITES[args.suite]
    build = os.path.abspath(args.build)
    ensure_built(build, not args.no_build, suite)
    t_start = time.monotonic()  # the benchmark's time excludes building
    work = os.path.abspath(args.work or os.path.join(build, suite.work))
    os.makedirs(work, exist_ok=True)
    unknown = set(args.cases.split(",")) - {c.name for c in suite.cases} if args.cases else set()
    if unknown:
        sys.exit(f"error: no case {', '.join(sorted(unknown))} in the {suite.name} suite")
    cases = [c for c in suite.cases if not args.cases or c.name in args.cases.split(",")]
    peer_params = load_peer_params(suite)
    methods = [v[0] for v in DETEXTURE_VARIANTS] + suite.peers
    if args.methods:
        methods = [m for m in methods if m in args.methods.split(",")]
    status = {}  # method -> reason it was skipped
    for peer in suite.peers:
        if peer not in methods:
            continue
        if peer_program(build, peer) is None:
            status[peer] = "not built" if peer != "meshlab-rimls" else "meshlabserver not installed"
        elif peer not in peer_params:
            status[peer] = f"no tuned parameters in bench/{os.path.basename(suite.peer_params_file)}"

    # Every run is single-threaded and `--jobs` (2) of them run at a time, so the
    # machine's 2 cores stay busy even while the single-threaded MeshLab RIMLS
    # runs; the longest runs start first (LPT), so the last ones to finish are
    # short. Each run is measured against its ground truth as soon as it ends, in
    # the same worker. The results do not depend on the order (every method is
    # deterministic, and the table is assembled by case and method).
    runs = {}  # (case, method) -> {"out":..., "seconds":..., "error":...}
    jobs = []  # (estimated single-thread seconds, case, method, cmd, output)
    variants = dict((v[0], v[1]) for v in DETEXTURE_VARIANTS)
    for case in cases:
        ply, gt = synthesize(build, case, case.points, work)
        runs[(case.name, "input")] = {"out": ply, "seconds": None, "error": ""}
        for method in methods:
            if method in status:
                continue
            out = os.path.join(work, f"{case.name}.{method}.ply")
            if method in variants:
                # None: no options at all, not even the radius rule (auto mode).
                rule = detexture_rule(case) if variants[method] is not None else []
                cmd = [detexture_bin(build), ply, "-o", out, "-f", "-q", "--threads", "1",
                       "--stats", out[:-4] + ".stats.json"] + rule + (variants[method] or [])
            else:
                cmd = [peer_program(build, method), ply, out] + \
                    peer_args(method, peer_params[method]["params"], case, case.points, threads=1)
                cached = None if args.no_cache else cached_peer_run(cmd, out)
                if cached is not None:
                    runs[(case.name, method)] = {"out": out, "seconds": cached["seconds"], "error": "",
                                                 "cmd": cmd, "cached": cached["date"]}
                    log(f"{case.name:26s} {method:20s} {cached['seconds']:7.1f} s (cached, {cached['date']})")
                    continue
            jobs.append((estimated_seconds(method, case), case, method, cmd, out))
    jobs.sort(key=lambda j: -j[0])  # longest first; stable, so ties keep the suite's order

    def one(job):
        _, case, method, cmd, out = job
        if method not in variants and os.path.exists(out):
            os.remove(out)
        ok, stdout, msg = run(cmd, out[:-4] + ".log", args.timeout)
        if method in variants:
            secs = detexture_seconds(out[:-4] + ".stats.json") if ok else None
        else:
            secs = last_seconds(stdout) if ok else None
            if ok:
                store_peer_run(cmd, out, secs)
        metrics = compare(build, out, os.path.join(work, case.name + ".gt.ply")) if ok else None
        return case, method, {"out": out, "seconds": secs, "error": msg, "cmd": cmd, "metrics": metrics}

    log(f"{len(jobs)} runs, {args.jobs} at a time, 1 thread each, longest first")
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        futures = [pool.submit(one, job) for job in jobs]
        for done, future in enumerate(concurrent.futures.as_completed(futures), 1):
            case, method, r = future.result()
            runs[(case.name, method)] = r
            log(f"[{done:2d}/{len(jobs)}] {case.name:26s} {method:20s} "
                + (f"{r['seconds']:7.1f} s" if not r["error"] else f"FAILED {r['error']}"))

    # The inputs and the cached peer runs are measured here.
    def measure(key):
        gt = os.path.join(work, key[0] + ".gt.ply")
        return key, compare(build, runs[key]["out"], gt)

    rest = [k for k, r in runs.items() if "metrics" not in r and not r["error"]]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for key, m in pool.map(measure, rest):
            runs[key]["metrics"] = m
    for r in runs.values():
        r.setdefault("metrics", None)
    with open(os.path.join(work, "metrics.json"), "w") as f:
        json.dump({f"{c.name}/{m}": runs[(c.name, m)] for c in cases for m in ["input"] + methods
                   if (c.name, m) in runs}, f, indent=1)
    active = [m for m in methods if m not in status]
    pictures = None if args.no_pictures else draw_pictures(build, cases, active, runs, work, args.jobs)
    total = time.monotonic() - t_start
    log(f"benchmark done in {total:.0f} s")
    text = render(suite, cases, methods, status, runs, peer_params, total, args, pictures)
    if args.no_results:
        print(text)
    else:
        write_results(text, suite)
        log(f"wrote the {suite.name} section of {RESULTS_FILE}")


def best_peer(case, active, runs):
    """The peer with the best mean of its ranks (among the peers) on residual
    texture and on normal error in this case; None when no peer has metrics."""
    peers = [m for m in active if m in PEER_LABEL and runs.get((case.name, m), {}).get("metrics")]
    if not peers:
        return None
    score = {m: 0.0 for m in peers}
    for key in ("signed_std", "normal_angle_mean_degrees"):
        for m, rk in zip(peers, rank([runs[(case.name, m)]["metrics"][key] for m in peers])):
            score[m] += rk
    return min(peers, key=lambda m: score[m])  # ties: the first in the suite's order


def draw_pictures(build, cases, active, runs, work, jobs):
    """Before/after pictures of every case (input, full method, best peer) with
    `detexture render`, into WORK/pictures/CASE.png; None (and a note) when the
    build has no render command. Returns {case name: (png path, peer)}."""
    # Without a render command, the main command takes "render" for its input
    # file and prints its own help, with exit code 0 too.
    probe = subprocess.run([detexture_bin(build), "render", "--help"], stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, text=True)
    main_help = subprocess.run([detexture_bin(build), "--help"], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True).stdout
    if probe.returncode != 0 or probe.stdout == main_help:
        log("note: this build has no `detexture render` command; pictures skipped")
        return None
    folder = os.path.join(work, "pictures")
    os.makedirs(folder, exist_ok=True)
    todo = []
    for case in cases:
        peer = best_peer(case, active, runs)
        clouds = [os.path.join(work, case.name + ".ply")]
        for m in ("detexture", peer):
            r = runs.get((case.name, m))
            if m and r and not r["error"]:
                clouds.append(r["out"])
        png = os.path.join(folder, case.name + ".png")
        labels = ["input", "detexture", method_label(peer) if peer else ""][:len(clouds)]
        todo.append((case, peer, png, [detexture_bin(build), "render"] + clouds
                     + ["-o", png, "--view", "iso", "--up", case.mesh.up if case.mesh else "z",
                        "--size", f"{500 * len(clouds)}x500", "-f", "--label"] + labels))

    def one(item):
        case, peer, png, cmd = item
        ok, _, msg = run(cmd, png[:-4] + ".log", 300)
        return case, peer, png, ok, msg

    done = {}
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        for case, peer, png, ok, msg in pool.map(one, todo):
            if ok:
                done[case.name] = (png, peer)
            else:
                log(f"note: picture of {case.name} failed: {msg}")
    log(f"wrote {len(done)} pictures to {folder}")
    return done


def file_digest(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def peer_run_key(cmd):
    """What a peer's output depends on: its program, its input and its options."""
    program, inp, _out, *options = cmd
    return {"program": file_digest(program), "input": file_digest(inp), "options": options}


def cached_peer_run(cmd, out):
    """The stored result of exactly this peer run, if its output is still there."""
    meta = out[:-4] + ".cache.json"
    if not (os.path.exists(meta) and os.path.exists(out)):
        return None
    with open(meta) as f:
        stored = json.load(f)
    if stored.get("key") != peer_run_key(cmd) or stored.get("output") != file_digest(out):
        return None
    return stored


def store_peer_run(cmd, out, seconds):
    with open(out[:-4] + ".cache.json", "w") as f:
        json.dump({"key": peer_run_key(cmd), "output": file_digest(out), "seconds": seconds,
                   "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M")}, f, indent=1)


def method_label(m):
    return PEER_LABEL.get(m, m)


def command_line(suite):
    """The wrapper's command line as the user typed it (without --suite)."""
    argv, shown, skip = sys.argv[2:], [], False
    for a in argv:
        if skip:
            skip = False
        elif a == "--suite":
            skip = True
        elif not a.startswith("--suite="):
            shown.append(a)
    return " ".join([suite.command] + shown)


def render(suite, cases, methods, status, runs, peer_params, total, args, pictures):
    L = []
    cmd = command_line(suite)
    L.append(f"## {suite.title}")
    L.append("")
    L.append(f"Produced by `{cmd}` on {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}, "
             f"{machine_description()}, detexture {git_revision()}. "
             f"Whole run (synthesis, all methods, all comparisons): **{total / 60:.1f} min**, "
             f"{args.jobs} runs at a time with one thread each, longest first "
             f"(machine shared with other work, so times are noisy). "
             f"Suite, parameter rule and peer tuning: bench/README.md.")
    cached = sorted({r["cached"] for r in runs.values() if r.get("cached")})
    if cached:
        n = sum(1 for r in runs.values() if r.get("cached"))
        L.append("")
        L.append(f"† {n} peer runs were taken from identical earlier runs (same program, input and "
                 f"options; made {cached[0]}" + (f" to {cached[-1]}" if len(cached) > 1 else "") + ") instead of being rerun, and their seconds are from "
                 f"then; the run time above excludes them (`--no-cache` reruns everything).")
    L.append("")
    L.append("Columns: distances to the ground-truth surface (point-to-plane at the nearest "
             "ground-truth sample, model units; every base shape fits the unit box): Dmean, Dmax, "
             "σ (the paper's Table 3); *residual texture* = standard deviation of the signed distance "
             "(texture and noise left); normal error = mean angle to the true normal, and share within "
             "10°; coverage mean = mean distance from a ground-truth sample to the nearest result point "
             "(holes, clustering); seconds = the method's own wall time (no I/O) on **one thread** "
             f"(every method runs single-threaded, {args.jobs} runs at a time; the multi-threaded "
             "ones are faster than this with more threads; MeshLab RIMLS stops after "
             f"{RIMLS_PROJECTION_ITERS} projection steps per point, see bench/README.md). "
             "Best value per case among the methods in **bold** (not for Dmax, coverage, seconds).")
    L.append("")
    # Method descriptions
    L.append("| method | what | parameters |")
    L.append("|---|---|---|")
    for name, extra, what in DETEXTURE_VARIANTS:
        if name in methods:
            if extra is None:
                L.append(f"| {name} | {what} | none: `detexture IN -o OUT` |")
            else:
                L.append(f"| {name} | {what} | r = 1.5 R, σs = r{(', `' + ' '.join(extra) + '`') if extra else ''} |")
    for peer in suite.peers:
        if peer not in methods:
            continue
        if peer in status:
            L.append(f"| {method_label(peer)} | skipped: {status[peer]} | |")
        else:
            p = peer_params[peer]["params"]
            L.append(f"| {method_label(peer)} | peer, tuned (bench/{os.path.basename(suite.peer_params_file)}) "
                     f"| {params_label(peer, p)} |")
    L.append("")

    active = [m for m in methods if m not in status]
    best_keys = ["dmean", "dstd", "signed_std", "normal_angle_mean_degrees"]
    for case in cases:
        L.append(f"### {case.name}")
        L.append("")
        mesh = ""
        if case.mesh:
            mesh = (f" Base mesh: {case.mesh.what}; `prepare_mesh {case.mesh.model} "
                    f"meshes/{case.mesh.name}.ply {' '.join(case.mesh.prepare_args())}`.")
        area = case.base()[0]
        within = case.density(case.points) * math.pi * (RADIUS_FACTOR * case.size) ** 2
        L.append(f"{case.what}.{mesh} `detexture synth "
                 f"{' '.join(case.synth_args(case.points, f'meshes/{case.mesh.name}.ply' if case.mesh else None))}`"
                 f" (base area {area:.4g}: about {within:.0f} points within r); "
                 f"detexture `{' '.join(detexture_rule(case))}`.")
        if pictures and case.name in pictures:
            png, peer = pictures[case.name]
            L.append("")
            L.append(f"Picture (not committed): `pictures/{case.name}.png` in the work folder: input, "
                     f"detexture, {method_label(peer) if peer else 'no peer'} (the best peer here).")
        L.append("")
        L.append("| method | " + " | ".join(h for h, _, _ in METRIC_COLUMNS) + " | Dmax ÷ input | seconds |")
        L.append("|---|" + "---:|" * (len(METRIC_COLUMNS) + 2))
        input_metrics = runs.get((case.name, "input"), {}).get("metrics")
        best = {}
        for k in best_keys:
            vals = [runs[(case.name, m)]["metrics"][k] for m in active
                    if runs.get((case.name, m), {}).get("metrics")]
            best[k] = min(vals) if vals else None
        best["normals_within_10_degrees_percent"] = max(
            (runs[(case.name, m)]["metrics"]["normals_within_10_degrees_percent"] for m in active
             if runs.get((case.name, m), {}).get("metrics")), default=None)
        for m in ["input"] + active:
            r = runs.get((case.name, m))
            if r is None:
                continue
            if r.get("metrics") is None:
                L.append(f"| {method_label(m)} | failed: {r['error']} |" + " |" * (len(METRIC_COLUMNS) + 1))
                continue
            cells = []
            for _, key, f in METRIC_COLUMNS:
                v = r["metrics"][key]
                s = "n/a" if v is None else f.format(v)
                if m != "input" and key in best and best[key] is not None and v == best[key]:
                    s = f"**{s}**"
                cells.append(s)
            ratio = dmax_ratio(r["metrics"], input_metrics)
            cells.append("" if ratio is None else f"{ratio:.2f}")
            secs = "" if r["seconds"] is None else f"{r['seconds']:.1f}" + ("†" if r.get("cached") else "")
            L.append(f"| {method_label(m)} | " + " | ".join(cells) + f" | {secs} |")
        L.append("")

    # Summary: mean ranks and wins across cases.
    L.append("### Summary across the suite")
    L.append("")
    L.append("Rank 1 = best in the case among the methods listed (input excluded); mean over the "
             f"{len(cases)} cases. Wins = cases where the method is best (ties count for each).")
    L.append("")
    L.append("| method | residual texture: mean rank | wins | normal error: mean rank | wins "
             "| Dmean: mean rank | wins | total seconds |")
    L.append("|---|---:|---:|---:|---:|---:|---:|---:|")
    summary = {m: {"res": [], "ang": [], "dmean": [], "secs": 0.0} for m in active}
    for case in cases:
        ms = [m for m in active if runs.get((case.name, m), {}).get("metrics")]
        for key, slot in (("signed_std", "res"), ("normal_angle_mean_degrees", "ang"), ("dmean", "dmean")):
            vals = [runs[(case.name, m)]["metrics"][key] for m in ms]
            for m, rk in zip(ms, rank(vals)):
                summary[m][slot].append(rk)
        for m in ms:
            summary[m]["secs"] += runs[(case.name, m)]["seconds"] or 0.0
    for m in active:
        s = summary[m]
        cells = []
        for slot in ("res", "ang", "dmean"):
            if s[slot]:
                cells.append(f"{sum(s[slot]) / len(s[slot]):.2f}")
                cells.append(str(sum(1 for x in s[slot] if x == 1.0)))
            else:
                cells += ["", ""]
        L.append(f"| {method_label(m)} | " + " | ".join(cells) + f" | {s['secs']:.0f} |")
    L.append("")

    # Per case: doing nothing, the full method, and the best peer on each metric.
    L.append("### Per case: input, full method, best peer")
    L.append("")
    L.append("The input row is doing nothing; the best peer is chosen per metric. "
             "Dmax ÷ input is the full method's Dmax over the input's.")
    L.append("")
    L.append("| case | residual texture: input | detexture | best peer | normal error °: input "
             "| detexture | best peer | Dmax ÷ input |")
    L.append("|---|---:|---:|---|---:|---:|---|---:|")
    worse = []
    for case in cases:
        inp = runs.get((case.name, "input"), {}).get("metrics")
        me = runs.get((case.name, "detexture"), {}).get("metrics") if "detexture" in active else None
        cells = []
        for key, f in (("signed_std", "{:.5f}"), ("normal_angle_mean_degrees", "{:.2f}")):
            cells.append(f.format(inp[key]) if inp else "")
            cells.append(f.format(me[key]) if me else "")
            peers = [(runs[(case.name, m)]["metrics"][key], m) for m in active
                     if m in PEER_LABEL and runs.get((case.name, m), {}).get("metrics")]
            cells.append(f"{f.format(min(peers)[0])} ({method_label(min(peers)[1])})" if peers else "")
        ratio = dmax_ratio(me, inp)
        cells.append("" if ratio is None else f"{ratio:.2f}")
        L.append(f"| {case.name} | " + " | ".join(cells) + " |")
        if me and inp:
            for label, key in (("residual texture", "signed_std"), ("normal error", "normal_angle_mean_degrees")):
                if me[key] > inp[key]:
                    worse.append(f"- {case.name}: {label} {me[key]:.4g} > input {inp[key]:.4g}")
            if ratio is not None and ratio > 1.25:
                worse.append(f"- {case.name}: Dmax {ratio:.2f} × the input's (over 1.25)")
    L.append("")
    if "detexture" in active:
        L.append("Where the full method is worse than the input (or Dmax over 1.25 × the input's):")
        L.append("")
        L += worse or ["- nowhere."]
        L.append("")

    # Where the full method is not best: listed automatically.
    if "detexture" in active:
        L.append("### Where the full method is not best")
        L.append("")
        lines = []
        for case in cases:
            me = runs.get((case.name, "detexture"), {}).get("metrics")
            if not me:
                lines.append(f"- {case.name}: the full method failed")
                continue
            for label, key, lower in (("residual texture", "signed_std", True),
                                      ("normal error", "normal_angle_mean_degrees", True),
                                      ("Dmean", "dmean", True)):
                better = []
                for m in active:
                    if m == "detexture":
                        continue
                    o = runs.get((case.name, m), {}).get("metrics")
                    if o and o[key] < me[key]:
                        better.append(f"{method_label(m)} {o[key]:.4g}")
                if better:
                    lines.append(f"- {case.name}, {label}: detexture {me[key]:.4g}; better: "
                                 + ", ".join(better))
        L += lines or ["- none: the full method is best on residual texture, normal error and Dmean in every case."]
        L.append("")
    if os.path.exists(suite.notes_file) and not args.cases and not args.methods:
        with open(suite.notes_file) as f:
            L.append(f.read().rstrip("\n"))
        L.append("")
    return "\n".join(L)


def dmax_ratio(metrics, input_metrics):
    if not metrics or not input_metrics or not input_metrics["dmax"]:
        return None
    return metrics["dmax"] / input_metrics["dmax"]


def write_results(text, suite):
    """Replace the suite's section of RESULTS.md (between its markers), adding
    the section at the end when the file does not have it yet."""
    if os.path.exists(RESULTS_FILE):
        with open(RESULTS_FILE) as f:
            content = f.read()
    else:
        content = "# detexture benchmark results\n\n" + SPEED_BEGIN + "\n" + SPEED_END + "\n"
    if suite.begin not in content or suite.end not in content:
        content = content.rstrip("\n") + "\n\n" + suite.begin + "\n" + suite.end + "\n"
    head, rest = content.split(suite.begin, 1)
    _, tail = rest.split(suite.end, 1)
    with open(RESULTS_FILE, "w") as f:
        f.write(head + suite.begin + "\n" + text.rstrip("\n") + "\n" + suite.end + tail)


def main():
    ap = argparse.ArgumentParser(prog="bench/quality_suite.py")
    sub = ap.add_subparsers(dest="command", required=True)
    default_build = os.environ.get("DETEXTURE_BUILD", os.path.join(REPO, "build"))
    q = sub.add_parser("quality", help="run the benchmark and write bench/RESULTS.md")
    t = sub.add_parser("tune", help="grid-search the peers and write bench/peer_params.json "
                                    "(bench/peer_params_real.json for --suite real)")
    for p in (q, t):
        p.add_argument("build", nargs="?", default=default_build,
                       help="build directory (default $DETEXTURE_BUILD or build)")
        p.add_argument("--suite", choices=sorted(SUITES), default="quality",
                       help="quality: the synthetic shapes (default); real: the real-shape suite")
        p.add_argument("--work", help="folder for the clouds (default BUILD/bench-quality, bench-real, "
                                      "bench-tune or bench-tune-real)")
        p.add_argument("--no-build", action="store_true", help="fail instead of building what is missing")
        p.add_argument("--timeout", type=float, default=600, help="seconds per method run (default 600)")
    q.add_argument("--cases", help="comma-separated subset of cases (the table then covers only those)")
    q.add_argument("--methods", help="comma-separated subset of methods")
    q.add_argument("--no-cache", action="store_true",
                   help="rerun the peers even when an identical earlier run (same program, input and "
                        "options) left its output in the work folder")
    q.add_argument("--no-results", action="store_true", help="print the Markdown instead of writing RESULTS.md")
    q.add_argument("--no-pictures", action="store_true",
                   help="skip the before/after pictures (drawn only when the build has `detexture render`)")
    q.add_argument("--jobs", type=int, default=2,
                   help="runs at a time, 1 thread each, longest first (default 2: the machine's cores)")
    q.add_argument("--variant", action="append", default=[], metavar="NAME=OPTIONS",
                   help="an extra detexture row: the suite's rule plus OPTIONS (e.g. "
                        "anchor01='--anchor-surface 0.1'), to measure a method change on both "
                        "suites before it lands; repeatable; combine with --methods and --no-results")
    t.add_argument("--points", type=int, default=TUNE_POINTS, help=f"points per case (default {TUNE_POINTS})")
    t.add_argument("--peers", help="comma-separated subset of peers")
    t.add_argument("--jobs", type=int, default=2, help="runs at a time, 1 thread each (default 2)")
    args = ap.parse_args()
    if args.command == "quality":
        for v in args.variant:
            name, sep, options = v.partition("=")
            if not sep or not name or name in {m[0] for m in DETEXTURE_VARIANTS} or "/" in name:
                sys.exit(f"error: --variant wants NAME=OPTIONS with a new NAME, got {v!r}")
            DETEXTURE_VARIANTS.append((name, shlex.split(options), "given with --variant"))
        quality(args)
    else:
        tune(args)


if __name__ == "__main__":
    main()
