#!/usr/bin/env python3
"""The `camplace export` viewer in a real browser (ctest label `browser`).

Runs `camplace export SCENE --cameras FILE --out DIR`, opens DIR/index.html from file:// in
headless Chromium (Debian's `chromium`, software WebGL through SwiftShader) and checks:
  1. no errors: the page records window errors, failed script loads, unhandled rejections and
     console.error calls in its #camplace-status element (read with --dump-dom), and Chromium's
     own log shows no uncaught error or failed load;
  2. every state's glTF loaded, with as many nodes per role as the scene file implies (counted
     here from the scene JSON, independently of camplace);
  3. the canvas is not blank: in a screenshot, the part right of the panel holds both the
     renderer's clear colour (WebGL drew) and enough pixels that differ from it (the scene).
The screenshot is kept (--artifact). Python 3 standard library only (PNG decoded with zlib).
"""
import argparse
import html
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

CLEAR_COLOUR = (0xDD, 0xE4, 0xEC)  # renderer.setClearColor in view/assets/page_common.js
PANEL_WIDTH = 300  # #panel's CSS width
WINDOW = (1200, 800)
CHROMIUM_FLAGS = [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader", "--hide-scrollbars", "--no-first-run",
    "--disable-dev-shm-usage",  # containers often have a tiny /dev/shm
    "--window-size=%d,%d" % WINDOW, "--virtual-time-budget=10000", "--enable-logging=stderr",
    "--v=0",
]


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def expected_roles(scene, h, l):
    """Node counts per role for state (h, l), from the scene file (docs/export.md)."""
    step = scene["time_steps"][h]
    dynamic = step.get("dynamic_obstacles", [])
    cameras = scene["cameras"]["count"]
    return {
        "static_obstacle": len(scene.get("static_obstacles", [])),
        "dynamic_obstacle": len(dynamic),
        "critical_object": len(step.get("critical", dynamic)),
        "target": len(step["events"][l]["targets"]),
        "model": 1,
        "camera": cameras,
        "fov": cameras,
        "true_distance": 1,
        "model_distance": 1,
    }


def run_chromium(chromium, page_url, extra, profile):
    command = [chromium] + CHROMIUM_FLAGS + ["--user-data-dir=" + profile] + extra + [page_url]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=180)
    return result.returncode, result.stdout.decode("utf-8", "replace"), \
        result.stderr.decode("utf-8", "replace")


def browser_log_errors(log):
    """Uncaught errors and failed loads in Chromium's console log lines."""
    errors = []
    for line in log.splitlines():
        if ":CONSOLE" in line and re.search(r"Uncaught|Failed to load|ERR_FILE", line):
            errors.append(line)
    return errors


def decode_png(path):
    """(width, height, rows of RGB tuples) of an 8-bit RGB or RGBA, non-interlaced PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(path + " is not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        fail("unsupported PNG (depth %d, colour type %d, interlace %d)" % (depth, colour, interlace))
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous, pos = [], bytearray(stride), 0
    for _ in range(height):
        kind, line = raw[pos], bytearray(raw[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):  # undo the row filter (PNG spec, section 9)
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + b) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 0xFF
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + predictor) & 0xFF
        rows.append([tuple(line[i:i + 3]) for i in range(0, stride, channels)])
        previous = line
    return width, height, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--camplace", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--cameras", required=True)
    parser.add_argument("--out", required=True, help="work directory (recreated)")
    parser.add_argument("--artifact", help="where to copy the screenshot")
    parser.add_argument("--chromium", default="chromium")
    args = parser.parse_args()

    if shutil.which(args.chromium) is None:
        fail(args.chromium + " not found (scripts/install_deps.sh installs Debian's chromium)")
    shutil.rmtree(args.out, ignore_errors=True)
    export_dir = os.path.join(args.out, "export")
    exported = subprocess.run([args.camplace, "export", args.scene, "--cameras", args.cameras,
                               "--out", export_dir], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=600)
    print(exported.stdout.decode())
    if exported.returncode != 0:
        fail("camplace export exited with %d" % exported.returncode)
    page = "file://" + os.path.abspath(os.path.join(export_dir, "index.html"))
    profile = os.path.join(args.out, "profile")

    # 1–2: the page's own report of what it loaded and what went wrong.
    code, dom, log = run_chromium(args.chromium, page, ["--dump-dom"], profile)
    match = re.search(r'<pre id="camplace-status">(.*?)</pre>', dom, re.S)
    if code != 0 or not match:
        print(log[-4000:])
        fail("chromium --dump-dom exited with %d and no #camplace-status element" % code)
    status = json.loads(html.unescape(match.group(1)))
    print("page status: " + json.dumps(status))
    problems = []
    if status.get("errors"):
        problems.append("errors in the page: %s" % status["errors"])
    problems += ["browser log: " + line for line in browser_log_errors(log)]
    if not status.get("ready"):
        problems.append("the page did not finish loading its glTF files")
    with open(args.scene) as f:
        scene = json.load(f)
    states = 0
    for h, step in enumerate(scene["time_steps"]):
        for l in range(len(step["events"])):
            states += 1
            name = "state-%d-%d" % (h, l)
            want = expected_roles(scene, h, l)
            got = status.get("states", {}).get(name)
            if got != want:
                problems.append("%s: nodes per role %s, the scene has %s" % (name, got, want))
    if len(status.get("states", {})) != states:
        problems.append("the page loaded %d states, the scene has %d"
                        % (len(status.get("states", {})), states))

    # 3: the screenshot.
    shot = os.path.join(args.out, "viewer.png")
    code, _, log = run_chromium(args.chromium, page, ["--screenshot=" + shot], profile)
    if code != 0 or not os.path.exists(shot):
        print(log[-4000:])
        fail("chromium --screenshot exited with %d" % code)
    if args.artifact:
        os.makedirs(os.path.dirname(os.path.abspath(args.artifact)), exist_ok=True)
        shutil.copyfile(shot, args.artifact)
        print("screenshot: " + args.artifact)
    width, height, rows = decode_png(shot)
    clear = differing = total = 0
    for row in rows:
        for pixel in row[PANEL_WIDTH + 20:]:
            total += 1
            distance = max(abs(pixel[c] - CLEAR_COLOUR[c]) for c in range(3))
            clear += distance <= 2
            differing += distance > 24
    print("screenshot %dx%d: right of the panel %d pixels, %d clear colour, %d differ from it"
          % (width, height, total, clear, differing))
    if clear < 0.05 * total:
        problems.append("the renderer's clear colour covers %d of %d pixels: WebGL did not draw"
                        % (clear, total))
    if differing < 0.05 * total:
        problems.append("only %d of %d pixels differ from the background: blank canvas"
                        % (differing, total))
    if problems:
        fail("\n  ".join(problems))
    print("PASS")


if __name__ == "__main__":
    main()
