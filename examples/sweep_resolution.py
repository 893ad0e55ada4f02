#!/usr/bin/env python3
"""Err of one camera configuration at several voxel resolutions, voxel against exact pipeline.

For each resolution and labelling mode, camplace.evaluate(pipeline="both") evaluates the
configuration with both pipelines (the voxel pipeline then uses the inscribed pyramid, as the
exact one does). The plot shows the voxel Err against the voxel diagonal with the exact Err as
the reference (left, log scale) and, per state, the voxel model's distance minus the exact one (right).
A table of the numbers goes to stdout.

From the repository root, after the build (README, "From Python"):

    PYTHONPATH=build/release/python python3 examples/sweep_resolution.py --out sweep.png
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402

import camplace  # noqa: E402


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="data/paper_basic.json", help="scene file")
    parser.add_argument("--cameras", default="data/paper_basic_corners.json",
                        help="camera file (or a run file of `camplace optimize`)")
    parser.add_argument("--resolutions", default="8x6x6,12x9x9,16x12x12,24x18x18,32x24x24",
                        help="comma-separated NXxNYxNZ list")
    parser.add_argument("--modes", default="center,conservative",
                        help="comma-separated voxel labelling modes")
    parser.add_argument("--threads", type=int, default=0, help="0 = one per core")
    parser.add_argument("--out", default="sweep_resolution.png", help="PNG file to write")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    scene = camplace.load_scene(args.scene)
    cameras = camplace.load_cameras(args.cameras, scene)
    resolutions = args.resolutions.split(",")
    modes = args.modes.split(",")

    # results[mode] = one evaluate() dict per resolution
    results = {
        mode: [camplace.evaluate(scene, cameras, pipeline="both", mode=mode, resolution=r,
                                 threads=args.threads) for r in resolutions]
        for mode in modes
    }
    exact_err = results[modes[0]][0]["exact"]["err"]  # the same at every resolution and mode

    print(f"{'mode':>12} {'resolution':>10} {'diagonal[m]':>11} {'Err voxel':>10} "
          f"{'Err exact':>10} {'tolerance':>10}")
    for mode in modes:
        for r in results[mode]:
            v = r["voxel"]
            print(f"{mode:>12} {'x'.join(map(str, v['resolution'])):>10} "
                  f"{v['voxel_diagonal']:11.4f} {v['err']:10.5f} {r['exact']['err']:10.5f} "
                  f"{v['tolerance']:10.5f}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6), dpi=80)
    for mode in modes:
        diagonal = [r["voxel"]["voxel_diagonal"] for r in results[mode]]
        left.plot(diagonal, [r["voxel"]["err"] for r in results[mode]], "o-",
                  label=f"voxel, {mode}")
    left.axhline(exact_err, color="black", linestyle="--", label="exact")
    left.set_xlabel("voxel diagonal [m]")
    left.set_ylabel("Err [m²]")
    left.set_yscale("log")  # center mode's Err can be 10⁵ times the exact one
    left.set_title(f"{scene.file}, {args.cameras}", fontsize=8)
    left.legend(fontsize=8)

    mode = modes[-1]
    diagonal = [r["voxel"]["voxel_diagonal"] for r in results[mode]]
    for index, state in enumerate(scene.states):
        right.plot(diagonal, [r["differences"]["states"][index]["d_model_voxel_minus_exact"]
                              for r in results[mode]], ".-",
                   label=f"h={state['time_step']}, l={state['event']}")
    right.axhline(0.0, color="black", linewidth=0.5)
    right.set_xlabel("voxel diagonal [m]")
    right.set_ylabel("d(C, M) voxel − exact [m]")
    right.set_title(f"per state, {mode}", fontsize=8)
    right.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(args.out)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
