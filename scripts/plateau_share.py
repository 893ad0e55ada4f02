#!/usr/bin/env python3
"""How flat is the plateau? Evaluates N random ceiling configurations of a scene whose
cameras all sit on the ceiling (default data/paper_ceiling.json, conservative mode) and prints how
many have Err = sum w d_true^2 (the model touches the critical objects in every state), and how
many distinct values the tie-breaker of `optimize --objective err+volume` (the weighted volume
of the model in the states where it touches the critical objects, over S's volume) takes among
them: distinct values give the solvers a direction.

    PYTHONPATH=build/release/python python3 scripts/plateau_share.py [SCENE] [N] [SEED] [room]

Pitch is drawn from [-90, 0] (the `ceiling` preset) and from [-90, 90] (the preset before
ceiling cameras were kept from looking up), yaw from [-180, 180], x and y from S, z = S's top; with `room` z is drawn from S and
pitch from [-90, 90] only (the `room` preset).
"""
import random
import sys

import camplace


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "data/paper_ceiling.json"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 500
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 14)
    scene = camplace.load_scene(path)
    lo, hi = scene.area["min"], scene.area["max"]
    volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])
    count = scene.camera_count
    room = len(sys.argv) > 4 and sys.argv[4] == "room"
    for pitch_hi in ((90.0,) if room else (0.0, 90.0)):
        on, fractions = 0, []
        for _ in range(n):
            cameras = [{"position": [rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]),
                                     rng.uniform(lo[2], hi[2]) if room else hi[2]],
                        "yaw_deg": rng.uniform(-180, 180), "pitch_deg": rng.uniform(-90, pitch_hi)}
                       for _ in range(count)]
            result = camplace.evaluate(scene, cameras, mode="conservative")
            states = result["states"]
            plateau = sum(s["weight"] * s["d_true"] ** 2 for s in states)
            if result["err"] >= plateau * (1 - 1e-9):  # sums in another order: relative slack
                on += 1
                weights = sum(s["weight"] for s in states)
                fractions.append(sum(s["weight"] * s["model_volume"] for s in states
                                     if s["d_model"] == 0.0) / (weights * volume))
        distinct = len({round(f, 9) for f in fractions})
        spread = f", tie-breaker {min(fractions):.3f}..{max(fractions):.3f}" if fractions else ""
        print(f"pitch in [-90, {pitch_hi:g}]: {on} of {n} random configurations on the plateau "
              f"Err = {plateau:.4f} m2; {distinct} distinct tie-breaker values among them{spread}")


if __name__ == "__main__":
    main()
