"""A textured shape before and after, drawn with numpy and matplotlib only.

    /usr/bin/python3 examples/python/before_after.py OUTPUT.png

Makes a plane with bumps (detexture.synthesize), removes the bumps, scores the
result against the exact plane, and draws both as height maps side by side.
"""
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

import detexture  # noqa: E402


def main():
    target = sys.argv[1]
    shape = detexture.synthesize(shape="plane", texture="bumps", size=0.06, amplitude=0.02,
                                 points=8000, ground_truth_points=8000, seed=2)
    result = detexture.remove_texture(shape.positions, shape.normals, radius=0.09)
    before = detexture.compare(shape.positions, shape.normals, shape.ground_truth_positions,
                               shape.ground_truth_normals)
    after = detexture.compare(result.positions, result.normals, shape.ground_truth_positions,
                              shape.ground_truth_normals)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True)
    for ax, P, title, c in ((axes[0], shape.positions, "before", before),
                            (axes[1], result.positions, "after", after)):
        im = ax.scatter(P[:, 0], P[:, 1], c=P[:, 2], s=3, cmap="viridis", vmin=-0.002,
                        vmax=0.02)
        ax.set_title(f"{title}: residual texture {c['signed_std']:.2g}")
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(im, ax=axes, label="height z")
    fig.savefig(target, dpi=80)
    print(f"residual texture {before['signed_std']:.3g} -> {after['signed_std']:.3g}, "
          f"{result.report.texture_points} texture points; wrote {target}")


if __name__ == "__main__":
    main()
