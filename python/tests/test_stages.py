"""The stages run alone give what remove_texture's pieces give, on cases
with known answers."""
import numpy as np
import pytest

import detexture


def bumpy_plane(side=41, amplitude=0.03, width=0.05):
    """A unit square grid at z = 0 with one Gaussian bump in the middle."""
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side), indexing="ij")
    h = amplitude * np.exp(-((x - 0.5) ** 2 + (y - 0.5) ** 2) / (2 * width ** 2))
    P = np.column_stack([x.ravel(), y.ravel(), h.ravel()])
    N = np.tile([0.0, 0.0, 1.0], (len(P), 1))
    return P, N, h.ravel()


def test_detect_texture_finds_the_bump():
    P, N, h = bumpy_plane()
    R = detexture.radius_neighborhoods(P, 0.08)
    t = detexture.detect_texture(P, R, N, lambda_=0.002)
    assert t["is_texture"].dtype == np.bool_
    assert t["is_texture"][h > 0.01].all()  # the top of the bump is texture
    assert not t["is_texture"][h < 1e-6].any()  # the far flat part is surface
    assert t["texture_points"] == int(t["is_texture"].sum())
    with pytest.raises(ValueError):  # λ has no default for a stage run alone
        detexture.detect_texture(P, R)
    with pytest.raises(TypeError, match="unexpected keyword argument 'texture_delta'"):
        detexture.detect_texture(P, R, lambda_=0.002, texture_delta=0.8)
    assert detexture.detect_texture(P, R, N, lambda_=0.002, delta=0.99)["texture_points"] >= \
        t["texture_points"]  # a larger δ marks more points texture
    with pytest.raises(ValueError, match="neighborhoods are of"):
        detexture.detect_texture(P[:10], R, lambda_=0.002)


def test_surface_split_parts_a_concave_crease():
    # A floor (z = 0, normals up) meeting a wall (x = 0.5, normals along -x):
    # never back to back, so only the split after detection parts them.
    g = np.linspace(0, 1, 41)
    floor = np.array([(x, y, 0.0) for x in g[g <= 0.5] for y in g])
    wall = np.array([(0.5, y, z) for z in g[(g > 0) & (g <= 0.5)] for y in g])
    P = np.vstack([floor, wall])
    N = np.vstack([np.tile([0.0, 0.0, 1.0], (len(floor), 1)),
                   np.tile([-1.0, 0.0, 0.0], (len(wall), 1))])
    R = detexture.radius_neighborhoods(P, 0.08)
    t = detexture.detect_texture(P, R, N, lambda_=0.002, surface_normals=True)
    assert "surface_normal" not in detexture.detect_texture(P, R, N, lambda_=0.002)
    assert not t["is_texture"].any()  # two planes: the crease is surface
    # Off the crease line (where both faces are at distance 0) each point's
    # surface is its own face.
    off_crease = np.hypot(P[:, 0] - 0.5, P[:, 2]) > 0.01
    assert np.allclose(t["surface_normal"][off_crease], N[off_crease], atol=1e-3)
    on_floor = P[:, 2] == 0
    across = sum(on_floor[i] != on_floor[j] for i in range(len(P)) for j in R[i])
    assert across > 0
    kept, removed = detexture.drop_neighbors_across_surfaces(R, N, t["surface_normal"],
                                                             t["is_texture"])
    assert removed == across
    assert all(on_floor[i] == on_floor[j] for i in range(len(P)) for j in kept[i])
    assert detexture.drop_neighbors_across_surfaces(R, N, t["surface_normal"], t["is_texture"],
                                                    max_angle_deg=180)[1] == 0
    with pytest.raises(ValueError, match="surface split angle"):
        detexture.drop_neighbors_across_surfaces(R, N, t["surface_normal"], t["is_texture"],
                                                 max_angle_deg=0)


def test_filters_and_update_flatten_the_bump():
    P, N, h = bumpy_plane()
    R = detexture.radius_neighborhoods(P, 0.08)
    t = detexture.detect_texture(P, R, N, lambda_=0.002)
    g = detexture.filter_normals_gaussian(P, N, R, t["omega"], sigma_s=0.08)
    r = detexture.filter_normals_rolling(P, N, g["normals"], R, t["omega"], sigma_s=0.08)
    assert np.allclose(np.linalg.norm(r["normals"], axis=1), 1.0)
    # The normals of a flat plane's filter are straight up.
    assert np.abs(r["normals"][:, 2]).min() > 0.99
    u = detexture.update_positions(P, r["normals"], R, t["is_texture"], sigma_p=0.04,
                                   solve_radius=0.04)
    assert np.abs(u["positions"][:, 2]).max() < 0.3 * h.max()  # the bump is mostly gone
    assert u["mean_displacement"] > 0
    with pytest.raises(ValueError, match="omega is needed"):
        detexture.filter_normals_gaussian(P, N, R, sigma_s=0.08)
    with pytest.raises(ValueError, match="is_texture is needed"):
        detexture.update_positions(P, N, R, sigma_p=0.04)


def test_fit_normals_to_positions_reads_a_sphere():
    # Exact sphere positions, guiding normals all tilted by 10°: the fit
    # gives the radial normals back, signed like the guide.
    n = 8000
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    a = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    P = np.column_stack([np.sqrt(1 - z * z) * np.cos(a), np.sqrt(1 - z * z) * np.sin(a), z])
    t = np.radians(10)
    rot = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    guide = P @ rot.T
    R = detexture.radius_neighborhoods(P, 0.12)
    f = detexture.fit_normals_to_positions(P, guide, R, sigma=0.05, radius=0.1, blend_high_deg=0)
    assert f["kept"] == 0 and f["blended"] == 0
    assert np.degrees(np.arccos(np.clip((f["normals"] * P).sum(1), -1, 1))).max() < 0.5
    flipped = detexture.fit_normals_to_positions(P, -guide, R, sigma=0.05, radius=0.1,
                                                 blend_high_deg=0)
    assert np.allclose(flipped["normals"], -f["normals"])
    # The default blend: where the fit turns 10° from the guide (away from
    # the x axis, about which the guide was turned) it is past
    # blend_high_deg (2°), and the guide is kept.
    b = detexture.fit_normals_to_positions(P, guide, R, sigma=0.05, radius=0.1)
    far = np.abs(P[:, 0]) < 0.5
    assert b["blended"] >= far.sum()
    assert np.allclose(b["normals"][far], guide[far])
    # The open window (5-10°): the fit where it turns under 5° (near the x
    # axis), closer to the guide than the fit where it turns more; the
    # output without the blend has none.
    assert b["open"].shape == P.shape and 0 < b["open_blended"] < len(P)
    near = np.abs(P[:, 0]) > 0.99
    assert near.any() and np.allclose(b["open"][near], f["normals"][near])

    def angle(a, c):
        return np.degrees(np.arccos(np.clip((a * c).sum(1), -1, 1)))
    assert (angle(b["open"][far], guide[far]) < angle(f["normals"][far], guide[far])).all()
    assert b["waves"].dtype == bool and b["waves"].shape == (len(P),)
    assert f["open"] is None and f["waves"] is None
    with pytest.raises(ValueError, match="spatial scale"):
        detexture.fit_normals_to_positions(P, guide, R, sigma=0.0, radius=0.1)


def test_fit_normals_to_positions_takes_range_normals():
    # A 90° fold whose guiding normals are rounded over the neighborhood (as
    # a filter leaves them): weighed by the exact face normals, the fits next
    # to the crease stay on their own face; weighed by the guide, they lean
    # across. None is the guide itself.
    side = 41
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side), indexing="ij")
    x, y = x.ravel(), y.ravel()
    t = np.radians(90)
    right = x > 0.5
    P = np.column_stack([x, y, np.zeros_like(x)])
    P[right, 0] = 0.5 + (x[right] - 0.5) * np.cos(t)
    P[right, 2] = (x[right] - 0.5) * np.sin(t)
    N = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    N[right] = [-np.sin(t), 0.0, np.cos(t)]
    R = detexture.radius_neighborhoods(P, 0.1)
    rounded = np.array([N[R[i]].sum(0) for i in range(len(P))])
    rounded /= np.linalg.norm(rounded, axis=1)[:, None]
    kw = dict(sigma=0.04, radius=0.08, blend_high_deg=0, fine_ratio=0)
    by_guide = detexture.fit_normals_to_positions(P, rounded, R, **kw)["normals"]
    by_exact = detexture.fit_normals_to_positions(P, rounded, R, range_normals=N, **kw)["normals"]
    assert np.array_equal(
        detexture.fit_normals_to_positions(P, rounded, R, range_normals=rounded, **kw)["normals"],
        by_guide)
    near = np.abs(x - 0.5) <= 0.1

    def error(a):
        return np.degrees(np.arccos(np.clip((a[near] * N[near]).sum(1), -1, 1))).mean()
    assert error(by_guide) > 5.0 and error(by_exact) < 0.1 * error(by_guide)
    with pytest.raises(ValueError, match="range_normals"):
        detexture.fit_normals_to_positions(P, rounded, R, range_normals=N[:5], **kw)


def test_keep_input_normals_where_nothing_moved():
    # A flat grid whose centre point moved by 1: points farther than the
    # radius from it take their input normal, the others keep the output
    # normal; texture points keep it too. (The reach after the move test
    # would take the near ones from the far ones: off here.)
    side = 21
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side), indexing="ij")
    P = np.column_stack([x.ravel(), y.ravel(), np.zeros(side * side)])
    up = np.tile([0.0, 0.0, 1.0], (len(P), 1))
    tilted = np.tile([0.0, np.sin(0.2), np.cos(0.2)], (len(P), 1))
    moved = P.copy()
    centre = 10 * side + 10
    moved[centre, 2] += 1.0
    R = detexture.radius_neighborhoods(P, 0.12)
    texture = np.zeros(len(P), dtype=bool)
    texture[0] = True
    k = detexture.keep_input_normals(P, moved, up, tilted, R, texture, radius=0.11, lambda_=0.01,
                                     reached_angle_deg=0.0)
    near = np.linalg.norm(P - P[centre], axis=1) <= 0.11
    far = ~near & ~texture
    assert np.allclose(k["normals"][far], up[far]) and k["kept"] == far.sum()
    assert np.array_equal(k["normals"][near | texture], tilted[near | texture])
    with pytest.raises(ValueError, match="keep-input"):
        detexture.keep_input_normals(P, moved, up, tilted, R, radius=0.11, low=0.5, lambda_=0.01)


def test_limit_counter_moves_cuts_outward_moves_under_raised_relief():
    # Ten texture points went down by 1 (raised relief, h = 1); of the
    # others one rose by 0.8 and one by 0.1: at l = 0.25 they saturate at
    # 0.25 (0.25 tanh(t / 0.25)), or with soft=False the first is cut to 0.25.
    P = np.zeros((20, 3))
    P[:, 0] = np.arange(20)
    N = np.tile([0.0, 0.0, 1.0], (20, 1))
    moved = P.copy()
    moved[:10, 2] = -1.0
    moved[10, 2], moved[11, 2] = 0.8, 0.1
    texture = np.arange(20) < 10
    c = detexture.limit_counter_moves(P, moved, N, texture, height=1.0, limit=0.25)
    assert c["lean"] == 1.0 and c["side"] == 1 and c["limited"] == 1
    expected = moved.copy()
    expected[10, 2], expected[11, 2] = 0.25 * np.tanh(3.2), 0.25 * np.tanh(0.4)
    assert np.allclose(c["positions"], expected, rtol=0, atol=1e-15)
    hard = detexture.limit_counter_moves(P, moved, N, texture, height=1.0, limit=0.25, soft=False)
    expected = moved.copy()
    expected[10, 2] = 0.25
    assert np.array_equal(hard["positions"], expected)
    # Released by the waves pass (session 27): point 10 keeps its 0.8; the
    # default limit is l = 0.125, so point 11 saturates at 0.125 tanh(0.8),
    # past l / 2: counted.
    released = np.zeros(20, dtype=bool)
    released[10] = True
    freed = detexture.limit_counter_moves(P, moved, N, texture, released, height=1.0)
    expected = moved.copy()
    expected[11, 2] = 0.125 * np.tanh(0.8)
    assert np.allclose(freed["positions"], expected, rtol=0, atol=1e-15) and freed["limited"] == 1
    held = detexture.limit_counter_moves(P, moved, N, texture, released, height=1.0,
                                         free_released=False)
    assert held["positions"][10, 2] < 0.125 and held["limited"] == 2
    with pytest.raises(ValueError, match="released"):
        detexture.limit_counter_moves(P, moved, N, texture, released[:5], height=1.0)
    off = detexture.limit_counter_moves(P, moved, N, texture, height=1.0, limit=0.0)
    assert np.array_equal(off["positions"], moved) and off["limited"] == 0
    with pytest.raises(ValueError, match="counter-move-limit"):
        detexture.limit_counter_moves(P, moved, N, texture, height=1.0, limit=-1.0)


def test_limit_tip_moves_holds_the_tops_and_bottoms_of_relief():
    # A cone on a 5 x 5 grid of spacing 1, z = -0.5 × the distance from the
    # centre, normals +z; λ = 0.1, ρ = 1.5: the top moved out by 0.3 ends at
    # the slack 0.1 above itself (its highest neighbor), sideways moves
    # stay; moved in, it is free. Upside down, the bottom is held the other way.
    g = np.arange(5.0) - 2.0
    x, y = (a.ravel() for a in np.meshgrid(g, g, indexing="xy"))
    N = np.tile([0.0, 0.0, 1.0], (25, 1))
    for sign in (1.0, -1.0):
        P = np.column_stack([x, y, -sign * 0.5 * np.hypot(x, y)])
        R = detexture.radius_neighborhoods(P, 1.5)
        moved = P.copy()
        moved[12] += [0.05, 0.0, sign * 0.3]
        c = detexture.limit_tip_moves(P, moved, N, R, radius=1.5, lambda_=0.1)
        expected = moved.copy()
        expected[12, 2] = sign * 0.1
        assert c["limited"] == 1 and np.allclose(c["positions"], expected, rtol=0, atol=1e-15)
        back = P.copy()
        back[12, 2] -= sign * 0.3
        free = detexture.limit_tip_moves(P, back, N, R, radius=1.5, lambda_=0.1)
        assert free["limited"] == 0 and np.array_equal(free["positions"], back)
    off = detexture.limit_tip_moves(P, moved, N, R, radius=1.5, lambda_=0.1, depth=0.0)
    assert off["limited"] == 0 and np.array_equal(off["positions"], moved)
    with pytest.raises(ValueError, match="tip-slack"):
        detexture.limit_tip_moves(P, moved, N, R, radius=1.5, lambda_=0.1, slack=-1.0)


def test_limit_sink_moves_holds_points_under_relief_at_their_own_depth():
    # A 5 x 5 grid of spacing 1 on z = 0, normals +z, each point 0.1 from
    # its fitted surface; point 13 raised by 0.5 beside the centre (12).
    # λ = 0.1, ρ = 1.5, depth 2 (0.2), slack 3 (0.3): the centre sunk by 1
    # stops at 0.1 + 0.3 below its input (no texture height given), sideways
    # moves stay. Without the relief above it (a top), not raised, or slack
    # 0: unchanged.
    g = np.arange(5.0) - 2.0
    x, y = (a.ravel() for a in np.meshgrid(g, g, indexing="xy"))
    N = np.tile([0.0, 0.0, 1.0], (25, 1))
    height = np.full(25, 0.1)
    P = np.column_stack([x, y, np.zeros(25)])
    P[13, 2] = 0.5
    R = detexture.radius_neighborhoods(P, 1.5)
    moved = P.copy()
    moved[12] += [0.05, 0.0, -1.0]
    c = detexture.limit_sink_moves(P, moved, N, height, R, True, radius=1.5, lambda_=0.1)
    expected = moved.copy()
    expected[12, 2] = -0.4
    assert c["limited"] == 1 and np.allclose(c["positions"], expected, rtol=0, atol=1e-7)
    # The texture height is a floor: with 0.6 the centre sinks to 0.6.
    c = detexture.limit_sink_moves(P, moved, N, height, R, True, radius=1.5, lambda_=0.1,
                                   height=0.6)
    expected[12, 2] = -0.6
    assert c["limited"] == 1 and np.allclose(c["positions"], expected, rtol=0, atol=1e-12)
    flat = P.copy()
    flat[13, 2] = 0.0
    top_moved = flat.copy()
    top_moved[12, 2] = -1.0
    Rf = detexture.radius_neighborhoods(flat, 1.5)
    for kept in (detexture.limit_sink_moves(flat, top_moved, N, height, Rf, True, radius=1.5,
                                            lambda_=0.1),
                 detexture.limit_sink_moves(P, moved, N, height, R, False, radius=1.5,
                                            lambda_=0.1),
                 detexture.limit_sink_moves(P, moved, N, height, R, True, radius=1.5,
                                            lambda_=0.1, slack=0.0)):
        assert kept["limited"] == 0
    with pytest.raises(ValueError, match="sink-slack"):
        detexture.limit_sink_moves(P, moved, N, height, R, True, radius=1.5, lambda_=0.1,
                                   slack=-1.0)


def test_lower_raised_cells_sinks_the_tops_to_the_gaps():
    # A 21 x 21 grid of spacing 1, every third row and column a gap at z = 0
    # and the cells at 0.3; the update left every point at 0.3, normals +z.
    # Read as dense raised cells (lean -0.8, 5 of 9 points texture), every
    # point sinks to 0, the gaps' level; leaning raised, nothing moves.
    g = np.arange(21.0)
    x, y = (a.ravel() for a in np.meshgrid(g, g, indexing="xy"))
    gap = (x % 3 == 0) | (y % 3 == 0)
    P = np.column_stack([x, y, np.where(gap, 0.0, 0.3)])
    tops = np.column_stack([x, y, np.full(len(x), 0.3)])
    N = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    texture = np.arange(len(x)) % 9 < 5
    R = detexture.radius_neighborhoods(P, 2.5)
    c = detexture.lower_raised_cells(P, tops, N, texture, -0.8, R, radius=2.5)
    assert c["applied"] and c["lowered"] == len(x)
    assert np.allclose(c["positions"][:, 2], 0.0, rtol=0, atol=1e-15)
    assert np.array_equal(c["positions"][:, :2], tops[:, :2])
    raised = detexture.lower_raised_cells(P, tops, N, texture, 0.8, R, radius=2.5)
    assert not raised["applied"] and np.array_equal(raised["positions"], tops)
    off = detexture.lower_raised_cells(P, tops, N, texture, -0.8, R, radius=2.5, enabled=False)
    assert off["lowered"] == 0 and np.array_equal(off["positions"], tops)
    with pytest.raises(ValueError, match="cells-low-quantile"):
        detexture.lower_raised_cells(P, tops, N, texture, -0.8, R, radius=2.5, low_quantile=2.0)
    # With the texture height (0.3) the depth limit, 1.25 of it below each
    # input, holds nothing back; at max_depth 0.5 the cells stop halfway.
    # A cell whose output normal points down, against its neighbors', sinks
    # along their mean to the feet; along its own it would rise to 0.6.
    turned = np.flatnonzero(~gap)[0]
    flipped = N.copy()
    flipped[turned] = [0.0, 0.0, -1.0]
    h = detexture.lower_raised_cells(P, tops, flipped, texture, -0.8, R, radius=2.5, height=0.3)
    assert h["turned"] == 1 and h["limited"] == 0
    assert np.allclose(h["positions"][:, 2], 0.0, rtol=0, atol=1e-15)
    up = detexture.lower_raised_cells(P, tops, flipped, texture, -0.8, R, radius=2.5, height=0.3,
                                      max_turn_deg=180.0)
    assert up["turned"] == 0 and abs(up["positions"][turned, 2] - 0.6) < 1e-15
    half = detexture.lower_raised_cells(P, tops, N, texture, -0.8, R, radius=2.5, height=0.3,
                                        max_depth=0.5)
    assert np.allclose(half["positions"][:, 2], np.where(gap, 0.0, 0.15), rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="cells-max-turn"):
        detexture.lower_raised_cells(P, tops, N, texture, -0.8, R, radius=2.5, max_turn_deg=0.0)
