"""detexture.remove_texture against the command line, its inputs, errors,
GIL release and cancellation."""
import json
import threading
import time

import numpy as np
import pytest

import detexture
from conftest import run_cli


def test_result_is_bitwise_the_command_lines(cube, work):
    out = work / "cli_out.ply"
    layer = work / "cli_layer.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--delta", "0.85", "--texture-fields",
            "--texture-layer", layer, "-q", "-j", "2", "--force")
    cloud = detexture.read_point_cloud(cube)
    r = detexture.remove_texture(cloud.positions, cloud.normals, radius=0.09, texture_delta=0.85,
                                 threads=2)
    cli = detexture.read_point_cloud(out)
    assert np.array_equal(cli.positions, r.positions)
    assert np.array_equal(cli.normals, r.normals)
    assert np.array_equal(cli.extras["texture"], r.is_texture.astype(np.uint8))
    assert np.array_equal(cli.extras["texture_height"], r.texture_height.astype(np.float32))
    # The files the library's texture_fields functions give are the CLI's, byte for byte.
    mine, mine_layer = work / "py_out.ply", work / "py_layer.ply"
    detexture.write_point_cloud(mine, detexture.detextured_cloud(cloud, r, texture_fields=True))
    detexture.write_point_cloud(mine_layer, detexture.texture_layer(cloud, r))
    assert mine.read_bytes() == out.read_bytes()
    assert mine_layer.read_bytes() == layer.read_bytes()
    # A PointCloud may be passed whole.
    again = detexture.remove_texture(cloud, radius=0.09, texture_delta=0.85, threads=1)
    assert np.array_equal(again.positions, r.positions)


def test_ignore_input_normals_is_the_command_lines(cube, work):
    out = work / "cli_ignored.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--ignore-normals", "-q", "--force")
    cloud = detexture.read_point_cloud(cube)
    r = detexture.remove_texture(cloud.positions, cloud.normals, radius=0.09,
                                 ignore_input_normals=True)
    bare = detexture.remove_texture(cloud.positions, radius=0.09)
    assert r.report.normals_ignored and r.report.normals_estimated
    assert not bare.report.normals_ignored
    assert np.array_equal(r.positions, bare.positions)
    assert np.array_equal(detexture.read_point_cloud(out).positions, r.positions)


def test_orient_side_is_the_command_lines(cube, work):
    """The cube's normals estimated and turned inward, as by --orient inward."""
    out = work / "cli_inward.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--ignore-normals", "--orient", "inward", "-q",
            "--force")
    cloud = detexture.read_point_cloud(cube)
    inward = detexture.remove_texture(cloud.positions, radius=0.09, orient_side="inward")
    named = detexture.remove_texture(cloud.positions, radius=0.09,
                                     orient_side=detexture.NormalSide.Inward)
    outward = detexture.remove_texture(cloud.positions, radius=0.09)
    centre = cloud.positions.mean(axis=0)
    facing = np.einsum("ij,ij->i", inward.input_normals, cloud.positions - centre)
    assert (facing < 0).mean() > 0.99
    assert np.array_equal(inward.input_normals, -outward.input_normals)
    assert np.array_equal(named.normals, inward.normals)
    assert np.array_equal(detexture.read_point_cloud(out).normals, inward.normals)
    assert detexture.default_parameters()["orient_side"] == detexture.NormalSide.Auto


def test_float32_and_any_layout_are_accepted(cube):
    cloud = detexture.read_point_cloud(cube)
    P = cloud.positions.astype(np.float32)
    ref = detexture.remove_texture(P.astype(np.float64), radius=0.09)
    assert np.array_equal(detexture.remove_texture(P, radius=0.09).positions, ref.positions)
    wide = np.zeros((len(P), 6), dtype=np.float32)
    wide[:, ::2] = P  # a strided view: every other column
    fortran = np.asfortranarray(P)
    for view in (wide[:, ::2], fortran):
        assert not view.flags.c_contiguous
        assert np.array_equal(detexture.remove_texture(view, radius=0.09).positions, ref.positions)


def test_result_arrays_and_report(cube):
    r = detexture.remove_texture(detexture.read_point_cloud(cube), radius=0.09)
    n = len(r)
    assert r.positions.shape == (n, 3) and r.positions.dtype == np.float64
    assert r.is_texture.dtype == np.bool_ and r.texture_height.shape == (n,)
    d = r.report.to_dict()
    assert d["texture_points"] == r.report.texture_points == int(r.is_texture.sum()) > 0
    assert d["radius"] == r.report.radius == 0.09
    assert d["radius_choice"] == "given"
    assert list(d["timings"])[0] == "spatial order"
    assert d["neighbors"]["mean"] == r.report.neighbors.mean > 10


def test_defaults_and_docs_come_from_the_cpp_struct():
    d = detexture.default_parameters()
    # The header's defaults (remove_texture.h, detect_texture.h, ...).
    assert d["radius"] == "1.5t" and d["lambda_"] == "0.05r" and d["sigma_s"] == "1r"
    assert d["texture_delta"] == 0.8 and d["texture_planes"] == 3 and d["threads"] == 0
    assert d["update_mode"] == detexture.UpdateMode.Global
    assert "update_max_move" not in d and "texture_lambda" not in d  # filled from above
    assert "texture_surface_normals" not in d
    doc = detexture.remove_texture.__doc__
    assert doc.startswith("remove_texture(points, normals=None, *, radius='1.5t',")
    assert "texture_delta : float, default 0.8" in doc
    assert "fraction of a point's neighborhoods in which it must be an inlier" in doc


def test_keywords_take_names_and_lengths(cube):
    P = detexture.read_point_cloud(cube).positions
    a = detexture.remove_texture(P, radius="0.09", update_mode="isotropic",
                                 rolling_guidance_mode="patch-shift", rolling_iterations=2)
    b = detexture.remove_texture(P, radius=0.09, update_mode=detexture.UpdateMode.Isotropic,
                                 rolling_guidance_mode=detexture.GuidanceMode.PatchShift,
                                 rolling_iterations=2)
    assert np.array_equal(a.positions, b.positions)
    assert a.report.rolling_iterations <= 2


def test_output_normals_match_the_command_line(cube, work):
    """The output normals' modes, the same from Python and from the command
    line. Fitted and blended output normals leave the positions as they are
    when the update fits the filtered normals (update_input_normals = False):
    by default it fits the exact input normals the fitted output would keep,
    and the filtered output keeps none."""
    cloud = detexture.read_point_cloud(cube)
    P = cloud.positions
    assert detexture.default_parameters()["fit_normals"] is True
    plain = detexture.remove_texture(cloud, radius=0.09, fit_normals=False)
    assert plain.report.input_normals_updated == 0
    runs = {"fitted": ({"output_normals_blend_high_deg": 0.0}, ["--output-normals", "fitted"]),
            "blended": ({}, [])}
    for name, (kwargs, args) in runs.items():
        out = work / f"{name}.ply"
        run_cli(cube, "-o", out, "-r", "0.09", "--fit-sigma", "0.25r", "-q", "--force",
                "--update-filtered-normals", *args)
        r = detexture.remove_texture(cloud, radius=0.09, fit_sigma="0.25r",
                                     update_input_normals=False, **kwargs)
        cli = detexture.read_point_cloud(out)
        assert np.array_equal(cli.normals, r.normals), name
        assert np.array_equal(plain.positions, r.positions), name
        assert not np.array_equal(plain.normals, r.normals), name
        assert r.report.normals_not_fitted < len(P) // 100
    out = work / "filtered.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "-q", "--force", "--output-normals", "filtered")
    assert np.array_equal(detexture.read_point_cloud(out).normals, plain.normals)
    assert plain.report.normals_blended == 0


def test_surface_split_matches_the_command_line(cube, work):
    assert detexture.default_parameters()["surface_split_max_angle_deg"] == 60.0
    out = work / "no_split.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--surface-split-angle", "180", "-q", "--force")
    cloud = detexture.read_point_cloud(cube)
    paper = detexture.remove_texture(cloud, radius=0.09, surface_split_max_angle_deg=180)
    split = detexture.remove_texture(cloud, radius=0.09)
    assert np.array_equal(detexture.read_point_cloud(out).positions, paper.positions)
    assert paper.report.surface_split_neighbors == 0
    assert split.report.surface_split_neighbors > 0
    assert not np.array_equal(paper.normals, split.normals)
    assert not np.array_equal(paper.positions, split.positions)


def test_anchor_angle_matches_the_command_line(cube, work):
    assert detexture.default_parameters()["anchor_angle"] == 15.0
    out = work / "no_anchor_angle.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--anchor-angle", "0", "-q", "--force")
    cloud = detexture.read_point_cloud(cube)
    blind = detexture.remove_texture(cloud, radius=0.09, anchor_angle=0)
    tilted = detexture.remove_texture(cloud, radius=0.09)
    assert np.array_equal(detexture.read_point_cloud(out).positions, blind.positions)
    assert np.array_equal(blind.is_texture, tilted.is_texture)  # detection is before the update
    assert not np.array_equal(blind.positions, tilted.positions)


def cli_error(*args):
    r = run_cli(*args, check=False)
    assert r.returncode != 0
    return r.stderr.strip().removeprefix("detexture: error: ")


def test_errors_raise_the_right_exception(cube, work):
    P = detexture.read_point_cloud(cube).positions
    with pytest.raises(ValueError, match=r"shape \(N, 3\), got \(10, 2\)"):
        detexture.remove_texture(np.zeros((10, 2)))
    with pytest.raises(ValueError, match="shape"):
        detexture.remove_texture(np.zeros(9))
    bad = P.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match="row 5 has a NaN"):
        detexture.remove_texture(bad)
    with pytest.raises(ValueError, match="empty"):
        detexture.remove_texture(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="as many rows"):
        detexture.remove_texture(P, np.zeros((3, 3)))
    # The same sentence as the command line's.
    message = cli_error(cube, "-o", work / "never.ply", "--delta", "1.5")
    with pytest.raises(ValueError) as e:
        detexture.remove_texture(P, texture_delta=1.5)
    assert str(e.value) == message
    with pytest.raises(ValueError):
        detexture.remove_texture(P, radius="3x")
    with pytest.raises(ValueError, match="one of Global, Isotropic, Eq9"):
        detexture.remove_texture(P, update_mode="sideways")
    with pytest.raises(TypeError, match="unexpected keyword argument 'delta'"):
        detexture.remove_texture(P, delta=0.8)
    with pytest.raises(TypeError):
        detexture.remove_texture(P, rolling_iterations=2.5)
    with pytest.raises(TypeError):
        detexture.remove_texture(P, reorient=1)


def test_the_gil_is_released_during_the_work(cube):
    P = detexture.read_point_cloud(cube).positions
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    # 20 rolling iterations with no early stop, so that the call lasts about
    # twice the 0.1 s asked below on a quiet machine.
    detexture.remove_texture(P, radius=0.15, threads=1, rolling_iterations=20,
                             rolling_tolerance_deg=0.0)
    end = time.perf_counter()
    done.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    assert end - start > 0.1
    # With the GIL held, the counting thread could not tick at all during the call.
    assert len(during) > 0.3 * (end - start) / 0.001 * 0.1


def test_progress_is_reported_and_an_exception_cancels(cube):
    P = detexture.read_point_cloud(cube).positions
    seen = []
    detexture.remove_texture(P, radius=0.09, progress=lambda s, f: seen.append((s, f)))
    stages = [s for s, _ in seen]
    assert "detect texture" in stages and "update positions" in stages
    assert all(0.0 <= f <= 1.0 for _, f in seen)

    class Stop(Exception):
        pass

    calls = []

    def stop_at_detection(stage, fraction):
        calls.append(stage)
        if stage == "detect texture":
            raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        detexture.remove_texture(P, radius=0.09, progress=stop_at_detection)
    assert "detect texture" in calls and "update positions" not in calls
    assert calls.count("detect texture") == 1  # no further calls after the exception
    with pytest.raises(TypeError):
        detexture.remove_texture(P, progress=3)


def test_wave_share_matches_the_command_line(work):
    """The second pass over waves left in the positions: on by default, off at
    wave_share_low = 1, the same from Python and from the command line."""
    assert detexture.default_parameters()["wave_share_low"] == 0.1
    assert detexture.default_parameters()["wave_share_high"] == 0.2
    torus = work / "torus_waves.ply"
    run_cli("synth", "--shape", "torus", "--texture", "waves", "--layout", "dense", "--size",
            "0.04", "--amplitude", "0.016", "-n", "30000", "--ground-truth-points", "100",
            "--seed", "1", "-o", torus)
    out = work / "torus_waves_off.ply"
    run_cli(torus, "-o", out, "-r", "0.06", "--wave-share-low", "1", "-q", "--force")
    cloud = detexture.read_point_cloud(torus)
    on = detexture.remove_texture(cloud, radius=0.06)
    off = detexture.remove_texture(cloud, radius=0.06, wave_share_low=1.0)
    assert on.report.waves_released > 0
    assert off.report.waves_released == 0
    assert on.report.waves_flagged == off.report.waves_flagged
    assert np.array_equal(detexture.read_point_cloud(out).positions, off.positions)
    assert not np.array_equal(on.positions, off.positions)
    # The fit's normals are the first pass's; the input normals kept where
    # nothing moved follow the final positions, so compare without them.
    fit_on = detexture.remove_texture(cloud, radius=0.06, keep_input_high=0.0)
    fit_off = detexture.remove_texture(cloud, radius=0.06, keep_input_high=0.0,
                                       wave_share_low=1.0)
    assert np.array_equal(fit_on.normals, fit_off.normals)
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.06, wave_share_low=0.3, wave_share_high=0.2)
    # The other surface points of the second pass (wave_rest_anchor): held
    # fully at 1, the same from Python and from the command line.
    second_pass_option_matches_cli(cloud, torus, work, on, "wave_rest_anchor", 0.3, 1.0)
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.06, wave_rest_anchor=0.0)
    # The second pass's ceiling (wave_ceiling): off at 0, and then fewer
    # moves limited.
    free = second_pass_option_matches_cli(cloud, torus, work, on, "wave_ceiling", 1.0, 0.0)
    assert on.report.tip_moves_limited > free.report.tip_moves_limited
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.06, wave_ceiling=-1.0)


def second_pass_option_matches_cli(cloud, torus, work, on, keyword, default, value):
    """The second pass's option `keyword` defaults to `default`; at `value`
    the output differs from `on` (the defaults' run) and is the same from
    Python and from the command line. Returns that output."""
    assert detexture.default_parameters()[keyword] == default
    out = work / f"torus_waves_{keyword}.ply"
    flag = "--" + keyword.replace("_", "-")
    run_cli(torus, "-o", out, "-r", "0.06", flag, str(value), "-q", "--force")
    changed = detexture.remove_texture(cloud, radius=0.06, **{keyword: value})
    assert np.array_equal(detexture.read_point_cloud(out).positions, changed.positions)
    assert not np.array_equal(on.positions, changed.positions)
    return changed


def default_and_option(cube, work, cli_args, **option):
    """remove_texture on the cube at defaults and with `option`; the command
    line given `cli_args` writes the same normals as the option, and the
    option leaves the positions as they were (an output-normal option). The
    update fits the filtered normals in all three runs
    (update_input_normals = False): by default it fits the exact input
    normals the keep_input tests take, so those options would move the
    positions too (tested in test_update_input_normals_match_the_command_line)."""
    cloud = detexture.read_point_cloud(cube)
    out = work / "option.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--update-filtered-normals", *cli_args, "-q",
            "--force")
    default = detexture.remove_texture(cloud, radius=0.09, update_input_normals=False)
    changed = detexture.remove_texture(cloud, radius=0.09, update_input_normals=False, **option)
    assert np.array_equal(detexture.read_point_cloud(out).normals, changed.normals)
    assert np.array_equal(default.positions, changed.positions)
    assert not np.array_equal(default.normals, changed.normals)
    return cloud, default, changed


def test_blend_share_matches_the_command_line(cube, work):
    """The blend's gate: on a cloud without waves left the output normals
    take the open window; blend_share_high = 0 keeps the blend's own window,
    the same from Python and from the command line."""
    d = detexture.default_parameters()
    assert (d["blend_share_low"], d["blend_share_high"]) == (0.05, 0.1)
    assert d["output_normals_blend_open_low_deg"] == 5.0
    assert d["output_normals_blend_open_high_deg"] == 10.0
    cloud, gated, always = default_and_option(
        cube, work, ["--blend-share-high", "0"], blend_share_high=0.0)
    assert gated.report.normals_blended < always.report.normals_blended
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.09, blend_share_low=0.3, blend_share_high=0.2)
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.09, output_normals_blend_open_low_deg=20.0)


def test_fine_fit_matches_the_command_line(cube, work):
    """The output normals' fine scale: on by default, fine_ratio = 0 fits at
    one scale; the positions do not change, the same from Python and from
    the command line."""
    d = detexture.default_parameters()
    assert (d["output_normals_fine_ratio"], d["output_normals_fine_gamma"]) == (0.5, 2.0)
    cloud, _, _ = default_and_option(
        cube, work, ["--fit-fine-ratio", "0"], output_normals_fine_ratio=0.0)
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.09, output_normals_fine_ratio=1.0)


def test_fit_range_normals_match_the_command_line(cube, work):
    """The output-normal fit's range weights read the input normals by
    default; fit_range_input_normals = False reads the filtered ones, the
    same from Python and from the command line, and the positions do not
    change."""
    assert detexture.default_parameters()["fit_range_input_normals"] is True
    cloud, _, _ = default_and_option(
        cube, work, ["--fit-range-normals", "filtered"], fit_range_input_normals=False)
    assert len(cloud.normals) == len(cloud.positions)


def test_keep_input_normals_match_the_command_line(cube, work):
    """Input normals are kept where nothing near the point moved (low 0.05,
    high 0.2, in units of λ), and exact ones (residual 0.05 λ over 8
    neighbors) within 4° of the fitted normal, and up to 20° where nothing
    moved by more than λ (facets, also found past their edges among 24
    neighbors, at least 4 of them); keep_input_high = 0,
    keep_input_exact_angle_deg = 0, keep_input_still_angle_deg = 0 and
    keep_input_reached_angle_deg = 0 (the reach after them, tested below)
    keep none, the same from Python and from the command line, and the positions
    do not change. The move alone and exactness alone each keep some (the
    cube is noise free), and both together more than either."""
    d = detexture.default_parameters()
    assert (d["keep_input_low"], d["keep_input_high"]) == (0.05, 0.2)
    assert (d["keep_input_exact_angle_deg"], d["keep_input_exact_residual"],
            d["keep_input_exact_neighbors"]) == (4.0, 0.05, 8)
    assert (d["keep_input_still_angle_deg"], d["keep_input_still_move"],
            d["keep_input_still_uniform_deg"]) == (20.0, 3.0, 1.0)
    assert d["keep_input_still_move_engraved"] == 1.0 and "keep_input_engraved" not in d
    assert (d["keep_input_facet_neighbors"], d["keep_input_facet_spread"],
            d["keep_input_facet_jump"], d["keep_input_facet_transitional"],
            d["keep_input_facet_members"], d["keep_input_facet_groups"]) == (24, 0.1, 3.0, 2, 4, 2)
    assert (d["keep_input_still_reach"], d["keep_input_still_facet_move"],
            d["keep_input_texture_facets"]) == (0.5, True, True)
    assert "keep_input_radius" not in d and "keep_input_lambda" not in d
    off = ["--keep-input-high", "0", "--keep-input-exact-angle", "0",
           "--keep-input-still-angle", "0", "--keep-input-reached-angle", "0"]
    cloud, kept, fitted = default_and_option(
        cube, work, off, keep_input_high=0.0, keep_input_exact_angle_deg=0.0,
        keep_input_still_angle_deg=0.0, keep_input_reached_angle_deg=0.0)
    assert kept.report.input_normals_kept > 0 and fitted.report.input_normals_kept == 0
    _, _, by_move = default_and_option(
        cube, work, ["--keep-input-exact-angle", "0", "--keep-input-still-angle", "0",
                     "--keep-input-reached-angle", "0"],
        keep_input_exact_angle_deg=0.0, keep_input_still_angle_deg=0.0,
        keep_input_reached_angle_deg=0.0)
    _, _, by_exactness = default_and_option(
        cube, work, ["--keep-input-high", "0"], keep_input_high=0.0)
    assert by_move.report.input_normals_kept > 0 and by_exactness.report.input_normals_kept > 0
    assert max(by_move.report.input_normals_kept,
               by_exactness.report.input_normals_kept) < kept.report.input_normals_kept
    with pytest.raises(ValueError):
        detexture.remove_texture(cloud, radius=0.09, keep_input_low=0.3)
    with pytest.raises(ValueError, match="exact-angle"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_exact_angle_deg=95.0)
    with pytest.raises(ValueError, match="still-move"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_still_move=-1.0)
    # Facets found past their edges (the cube's faces near its edges): off
    # takes fewer input normals.
    _, with_facets, without = default_and_option(
        cube, work, ["--keep-input-facet-neighbors", "0"], keep_input_facet_neighbors=0)
    assert without.report.input_normals_kept < with_facets.report.input_normals_kept
    with pytest.raises(ValueError, match="facet-neighbors"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_facet_neighbors=-1)
    with pytest.raises(ValueError, match="facet-members"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_facet_members=2)
    # The cone and the move over the whole ball (before session 25): the same
    # from both sides.
    default_and_option(
        cube, work, ["--keep-input-still-reach", "0", "--keep-input-still-any-move"],
        keep_input_still_reach=0.0, keep_input_still_facet_move=False)
    with pytest.raises(ValueError, match="still-reach"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_still_reach=1.0)


def test_update_input_normals_match_the_command_line(cube, work):
    """The update fits the exact input normals that the keep_input tests
    would take were nothing to move (session 43): on by default, where the
    noise-free cube's facets hold them; update_input_normals = False fits
    the filtered normals everywhere, the same from Python and from the
    command line (--update-filtered-normals), and moves the positions."""
    assert detexture.default_parameters()["update_input_normals"] is True
    cloud = detexture.read_point_cloud(cube)
    held = detexture.remove_texture(cloud, radius=0.09)
    filtered = detexture.remove_texture(cloud, radius=0.09, update_input_normals=False)
    assert held.report.input_normals_updated > 0.1 * len(cloud.positions)
    assert filtered.report.input_normals_updated == 0
    assert not np.array_equal(held.positions, filtered.positions)
    out = work / "update_filtered.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--update-filtered-normals", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, filtered.positions)
    # With the keep_input tests off, nothing is taken for the update either.
    none = detexture.remove_texture(cloud, radius=0.09, keep_input_exact_angle_deg=0.0,
                                    keep_input_still_angle_deg=0.0)
    assert none.report.input_normals_updated == 0


def test_reached_normals_match_the_command_line(cube, work):
    """Exact input normals the output normals reach (session 37): taken up
    to 30° from the fitted normal where some output normal within the solve
    radius lies within 0.15 of that angle of them, not where the relief reads
    as sparse engraving; keep_input_reached_angle_deg = 0 takes none this
    way, the same from Python and from the command line: fewer input normals
    kept, the positions unchanged. On the cube the earlier tests leave it
    nothing, so they are off here: it then reaches from the normals the move
    test took (facets where nothing moved) to exact ones beside them."""
    d = detexture.default_parameters()
    assert (d["keep_input_reached_angle_deg"], d["keep_input_reached_share"],
            d["keep_input_reached_engraved"]) == (30.0, 0.15, False)
    cloud = detexture.read_point_cloud(cube)
    alone = dict(keep_input_exact_angle_deg=0.0, keep_input_still_angle_deg=0.0)
    reached = detexture.remove_texture(cloud, radius=0.09, **alone)
    off = detexture.remove_texture(cloud, radius=0.09, keep_input_reached_angle_deg=0.0, **alone)
    out = work / "reached.ply"
    run_cli(cube, "-o", out, "-r", "0.09", "--keep-input-exact-angle", "0",
            "--keep-input-still-angle", "0", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).normals, reached.normals)
    assert np.array_equal(reached.positions, off.positions)
    assert off.report.input_normals_kept < reached.report.input_normals_kept
    with pytest.raises(ValueError, match="reached-angle"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_reached_angle_deg=90.0)
    with pytest.raises(ValueError, match="reached-share"):
        detexture.remove_texture(cloud, radius=0.09, keep_input_reached_share=0.0)


def test_still_move_reads_the_relief_side(work):
    """Where the relief reads as sparse engraving (V grooves on a pyramid:
    lean -1, grooves a small share of the cloud), the move under which the
    surface counts as stayed is keep_input_still_move_engraved (1 λ), not
    keep_input_still_move (3 λ): changing the latter changes nothing there,
    raising the former keeps more input normals (the groove walls), the same
    from Python and from the command line, positions unchanged."""
    pyramid = work / "pyramid_vgrooves.ply"
    run_cli("synth", "--shape", "pyramid", "--texture", "v-grooves", "--layout", "sparse",
            "--size", "0.03", "--amplitude", "0.01", "-n", "20000", "--ground-truth-points",
            "100", "--seed", "1", "-o", pyramid)
    cloud = detexture.read_point_cloud(pyramid)
    base = detexture.remove_texture(cloud, radius=0.045)
    assert base.report.relief_lean <= -0.5
    assert base.report.texture_points < 0.5 * len(cloud.positions)
    one = detexture.remove_texture(cloud, radius=0.045, keep_input_still_move=1.0)
    assert np.array_equal(one.normals, base.normals)
    walls = detexture.remove_texture(cloud, radius=0.045, keep_input_still_move_engraved=3.0)
    assert np.array_equal(walls.positions, base.positions)
    assert walls.report.input_normals_kept > base.report.input_normals_kept
    out = work / "pyramid_vgrooves_walls.ply"
    run_cli(pyramid, "-o", out, "-r", "0.045", "--keep-input-still-move-engraved", "3", "-q",
            "--force")
    assert np.array_equal(detexture.read_point_cloud(out).normals, walls.normals)
    with pytest.raises(ValueError, match="still-move-engraved"):
        detexture.remove_texture(cloud, radius=0.045, keep_input_still_move_engraved=-1.0)


def test_texture_facets_match_the_command_line(work):
    """Texture-labelled points take an exact input normal where their
    neighbors' input normals agree (on a pyramid with dense domes, beside
    its edges and domes): keep_input_texture_facets = False takes fewer,
    the same from Python and from the command line, positions unchanged."""
    pyramid = work / "pyramid_domes.ply"
    run_cli("synth", "--shape", "pyramid", "--texture", "domes", "--layout", "dense", "--size",
            "0.04", "--amplitude", "0.01", "-n", "20000", "--ground-truth-points", "100",
            "--seed", "1", "-o", pyramid)
    out = work / "pyramid_domes_surface_only.ply"
    run_cli(pyramid, "-o", out, "-r", "0.06", "--keep-input-surface-only",
            "--update-filtered-normals", "-q", "--force")
    cloud = detexture.read_point_cloud(pyramid)
    both = detexture.remove_texture(cloud, radius=0.06, update_input_normals=False)
    surface = detexture.remove_texture(cloud, radius=0.06, keep_input_texture_facets=False,
                                       update_input_normals=False)
    assert np.array_equal(detexture.read_point_cloud(out).normals, surface.normals)
    assert np.array_equal(both.positions, surface.positions)
    assert both.report.input_normals_kept > surface.report.input_normals_kept
    changed = np.any(both.normals != surface.normals, axis=1)
    assert changed.sum() > 0.02 * len(changed)
    assert np.all(both.is_texture[changed]) and np.array_equal(both.is_texture, surface.is_texture)


def test_counter_moves_match_the_command_line(work):
    """Under raised relief no point moves outward by more than an eighth of
    the texture height: a dent among raised bumps is filled by that much only
    (counter_moves_limit = 0 fills it), the same from Python and from the
    command line."""
    d = detexture.default_parameters()
    assert (d["counter_moves_limit"], d["counter_moves_min_lean"]) == (0.125, 0.35)
    assert d["counter_moves_free_released"] is True
    assert d["counter_moves_released_min_lean"] == 0.5
    assert d["counter_moves_count_from"] == 0.5 and d["counter_moves_engraved_share"] == 0.5
    assert d["counter_moves_soft"] is True and d["counter_moves_engraved_min_lean"] == 0.5
    assert "counter_moves_height" not in d
    u = np.linspace(0.0, 1.0, 61)
    x, y = (a.ravel() for a in np.meshgrid(u, u, indexing="ij"))
    du = x - (np.floor(x / 0.2) + 0.5) * 0.2
    dv = y - (np.floor(y / 0.2) + 0.5) * 0.2
    dent = (x - 0.6) ** 2 + (y - 0.6) ** 2
    z = 0.03 * (np.exp(-(du ** 2 + dv ** 2) / (2 * 0.03 ** 2)) - np.exp(-dent / (2 * 0.03 ** 2)))
    cloud = detexture.PointCloud(np.column_stack([x, y, z]), np.tile([0.0, 0.0, 1.0], (len(x), 1)))
    path = work / "dent.ply"
    detexture.write_point_cloud(path, cloud)
    limited = detexture.remove_texture(cloud, radius=0.1)
    free = detexture.remove_texture(cloud, radius=0.1, counter_moves_limit=0.0)
    h = limited.report.texture_height
    assert limited.report.relief_lean >= 0.35 and limited.report.counter_moves_limited > 0
    assert free.report.counter_moves_limited == 0
    assert (limited.positions[:, 2] - z).max() <= 0.125 * h + 1e-12
    i = np.argmin(dent)
    assert limited.positions[i, 2] < -0.015 < -0.0075 < free.positions[i, 2]
    out = work / "dent_free.ply"
    run_cli(path, "-o", out, "-r", "0.1", "--counter-move-limit", "0", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, free.positions)
    # Session 19's hard cut, from both: the same, and not the saturation.
    hard = detexture.remove_texture(cloud, radius=0.1, counter_moves_soft=False)
    assert not np.array_equal(hard.positions, limited.positions)
    out = work / "dent_hard.ply"
    run_cli(path, "-o", out, "-r", "0.1", "--counter-move-hard", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, hard.positions)
    with pytest.raises(ValueError, match="counter-move-lean"):
        detexture.remove_texture(cloud, radius=0.1, counter_moves_min_lean=0.0)
    with pytest.raises(ValueError, match="counter-move-engraved-share"):
        detexture.remove_texture(cloud, radius=0.1, counter_moves_engraved_share=1.5)
    with pytest.raises(ValueError, match="counter-move-released-lean"):
        detexture.remove_texture(cloud, radius=0.1, counter_moves_released_min_lean=0.0)


def test_raised_cells_match_the_command_line(work):
    """Dense raised cells are lowered to their feet (lower_raised_cells.h):
    on a sphere covered edge to edge in scales the output ends nearer the
    sphere than on the cells' tops (raised_cells_enabled = False, or
    --keep-cells-tops); the same from Python and from the command line,
    whose --stats reports the count."""
    d = detexture.default_parameters()
    assert (d["raised_cells_enabled"], d["raised_cells_low_quantile"],
            d["raised_cells_spread_quantile"], d["raised_cells_max_depth"],
            d["raised_cells_max_turn_deg"]) == (True, 0.02, 0.1, 1.25, 90.0)
    assert "raised_cells_radius" not in d and "raised_cells_min_lean" not in d
    assert "raised_cells_height" not in d  # the texture height the run finds
    sphere = work / "sphere_scales.ply"
    run_cli("synth", "--shape", "sphere", "--texture", "scales", "--layout", "dense",
            "--size", "0.03", "--amplitude", "0.01", "-n", "20000",
            "--ground-truth-points", "100", "--seed", "1", "-o", sphere)
    cloud = detexture.read_point_cloud(sphere)
    lowered = detexture.remove_texture(cloud, radius=0.045)
    tops = detexture.remove_texture(cloud, radius=0.045, raised_cells_enabled=False)
    assert lowered.report.raised_cells_lowered > 19000
    assert tops.report.raised_cells_lowered == 0
    off = lambda X: np.abs(np.linalg.norm(X, axis=1) - 0.5).mean()
    assert off(lowered.positions) < 0.5 * off(tops.positions)
    out, stats = work / "sphere_scales_lowered.ply", work / "sphere_scales_lowered.json"
    run_cli(sphere, "-o", out, "-r", "0.045", "--stats", stats, "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, lowered.positions)
    written = json.loads(stats.read_text())
    for key in ("raised_cells_lowered", "raised_cells_limited", "raised_cells_turned"):
        assert written[key] == getattr(lowered.report, key), key
    out = work / "sphere_scales_tops.ply"
    run_cli(sphere, "-o", out, "-r", "0.045", "--keep-cells-tops", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, tops.positions)


def test_sink_moves_match_the_command_line(work):
    """Under raised relief, a point that relief rises above sinks no deeper
    than the texture height, or its own height plus the slack
    (limit_sink_moves.h): on a saddle with multiscale bumps some points are
    held; sinks_slack = 0 turns it off; the same from Python and from the
    command line, whose --stats reports the count."""
    d = detexture.default_parameters()
    assert (d["sinks_depth"], d["sinks_slack"]) == (2.0, 3.0)
    assert not {"sinks_height", "sinks_radius", "sinks_lambda"} & set(d)
    saddle = work / "saddle_multiscale.ply"
    run_cli("synth", "--shape", "saddle", "--texture", "multiscale", "-n", "20000",
            "--ground-truth-points", "100", "--seed", "1", "-o", saddle)
    cloud = detexture.read_point_cloud(saddle)
    held = detexture.remove_texture(cloud)
    free = detexture.remove_texture(cloud, sinks_slack=0.0)
    assert held.report.sink_moves_limited > 10 and free.report.sink_moves_limited == 0
    assert held.report.relief_lean > 0.35
    assert not np.array_equal(held.positions, free.positions)
    out, stats = work / "saddle_multiscale_held.ply", work / "saddle_multiscale_held.json"
    run_cli(saddle, "-o", out, "--stats", stats, "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, held.positions)
    assert json.loads(stats.read_text())["sink_moves_limited"] == held.report.sink_moves_limited
    out = work / "saddle_multiscale_free.ply"
    run_cli(saddle, "-o", out, "--sink-slack", "0", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, free.positions)


def test_tip_moves_match_the_command_line(work):
    """The tops and bottoms of the relief do not end past their neighbors
    (limit_tip_moves.h): on a sphere with U grooves some groove floors are
    held; tips_depth = 0 turns it off (with wave_ceiling = 0, the ceiling
    on the waves' second pass, which the grooves run); the same from Python
    and from the command line, whose --stats reports the count."""
    d = detexture.default_parameters()
    assert (d["tips_depth"], d["tips_slack"]) == (2.0, 1.0)
    assert "tips_radius" not in d and "tips_lambda" not in d and "tips_ceiling" not in d
    assert d["tips_ceiling_min_cos"] == 0.5
    sphere = work / "sphere_u_grooves.ply"
    run_cli("synth", "--shape", "sphere", "--texture", "u-grooves", "-n", "20000",
            "--ground-truth-points", "100", "--seed", "1", "-o", sphere)
    cloud = detexture.read_point_cloud(sphere)
    held = detexture.remove_texture(cloud)
    free = detexture.remove_texture(cloud, tips_depth=0.0, wave_ceiling=0.0)
    assert held.report.tip_moves_limited > 10 and free.report.tip_moves_limited == 0
    assert not np.array_equal(held.positions, free.positions)
    out, stats = work / "sphere_u_grooves_held.ply", work / "sphere_u_grooves_held.json"
    run_cli(sphere, "-o", out, "--stats", stats, "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, held.positions)
    assert json.loads(stats.read_text())["tip_moves_limited"] == held.report.tip_moves_limited
    out = work / "sphere_u_grooves_free.ply"
    run_cli(sphere, "-o", out, "--tip-depth", "0", "--wave-ceiling", "0", "-q", "--force")
    assert np.array_equal(detexture.read_point_cloud(out).positions, free.positions)
    with pytest.raises(ValueError, match="tip-depth"):
        detexture.remove_texture(cloud, tips_depth=-1.0)
