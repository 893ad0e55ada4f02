#!/usr/bin/env python3
"""`camplace serve` end to end in a real browser (ctest label `browser`).

Starts `camplace serve SCENE --cameras FILE --resolution R --port 0`, refuses two requests
itself (no token: 403; malformed and out-of-range bodies: 400 with the `error:` text the
command line prints, and the server keeps running), then drives the planner page in headless
Chromium (Debian's `chromium`, software WebGL) through the DevTools protocol over
--remote-debugging-pipe (Python standard library only, no client to install):
  1. the page loads without errors and shows the configuration;
  2. camera 0 is moved by a known amount with the page's fields (typed with key events, applied
     with a mouse click); the update arrives with the camera where it was sent;
  3. the round trip (change sent → frame drawn with the answer) is measured over --moves moves
     and printed; then camera 0 is dragged along the x arrow of the TransformControls gizmo with
     mouse events: only x changes; then turned with the gizmo's rings: only the direction
     changes;
  4. the configuration is saved from the page and `camplace evaluate --json` of the saved file
     gives exactly the Err the page shows (and the same 6-decimal text);
  5. "check exactly" is cancelled after its first state, then run to the end (a move made
     meanwhile is answered at once): its exact Err is that of `camplace evaluate --pipeline both`;
  6. an optimisation is started from the page, streams progress, and is cancelled; the page
     shows its result;
  7. undo returns to the saved configuration; a camera is added and removed again;
  8. SIGINT stops the server cleanly (exit 0, "no unsaved changes").
Screenshots before and after the move are kept (--artifacts).
"""
import argparse
import base64
import fcntl
import json
import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import time
import urllib.error
import urllib.request

WINDOW = (1280, 800)
CHROMIUM_FLAGS = [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader", "--hide-scrollbars", "--no-first-run",
    "--disable-dev-shm-usage", "--window-size=%d,%d" % WINDOW, "--remote-debugging-pipe",
    "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
]


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


class Browser:
    """Chromium driven through the DevTools protocol on fds 3 (commands) and 4 (replies),
    messages as JSON ended by a NUL byte."""

    def __init__(self, chromium, profile):
        to_browser = os.pipe()
        from_browser = os.pipe()
        keep = (to_browser[0], from_browser[1])

        def child_fds():
            # Move both ends above 10 first: dup2 onto 3 must not close the other one.
            high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in keep]
            os.dup2(high[0], 3)
            os.dup2(high[1], 4)

        self.log = profile + ".log"
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen(
                [chromium] + CHROMIUM_FLAGS + ["--user-data-dir=" + profile, "about:blank"],
                stdout=subprocess.DEVNULL, stderr=log, preexec_fn=child_fds,
                close_fds=False)  # the pipes are close-on-exec (PEP 446); only 3 and 4 pass
        os.close(to_browser[0])
        os.close(from_browser[1])
        self.write_fd, self.read_fd = to_browser[1], from_browser[0]
        self.buffer = b""
        self.next_id = 0
        self.session = None

    def call(self, method, params=None, session=True, timeout=60):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        os.write(self.write_fd, json.dumps(message).encode() + b"\0")
        deadline = time.time() + timeout
        while time.time() < deadline:
            while b"\0" not in self.buffer:
                chunk = os.read(self.read_fd, 1 << 20)
                if not chunk:
                    with open(self.log) as log:
                        fail("chromium closed the DevTools pipe:\n" + log.read()[-3000:])
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    fail("DevTools %s: %s" % (method, reply["error"]))
                return reply.get("result", {})
        fail("DevTools %s: no reply in %d s" % (method, timeout))

    def open(self, url):
        targets = self.call("Target.getTargets", session=False)["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        self.session = self.call("Target.attachToTarget",
                                 {"targetId": page["targetId"], "flatten": True},
                                 session=False)["sessionId"]
        self.call("Page.enable")
        # The page's viewport itself (the window's size includes the browser's own frame).
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": WINDOW[0], "height": WINDOW[1], "deviceScaleFactor": 1,
                   "mobile": False})
        self.call("Page.navigate", {"url": url})

    def js(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                "awaitPromise": True})
        if "exceptionDetails" in result:
            fail("page script %r: %s" % (expression, result["exceptionDetails"]))
        return result["result"].get("value")

    def status(self):
        return self.js("JSON.parse(JSON.stringify(window.camplaceStatus || {}))")

    def wait(self, what, predicate, timeout=60):
        deadline = time.time() + timeout
        while time.time() < deadline:
            s = self.status()
            if predicate(s):
                return s
            time.sleep(0.02)
        fail("timed out waiting for %s; page status: %s" % (what, json.dumps(self.status())[:3000]))

    def centre(self, element_id):
        r = self.js("(function(){var r=document.getElementById(%r).getBoundingClientRect();"
                    "return [r.left + r.width / 2, r.top + r.height / 2];})()" % element_id)
        return r

    def click(self, element_id):
        x, y = self.centre(element_id)
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent",
                      {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1})

    def type_into(self, element_id, text):
        """Focuses the field with a click, selects its content and types `text` as key events."""
        self.click(element_id)
        self.js("document.getElementById(%r).select()" % element_id)
        self.call("Input.insertText", {"text": text})

    def screenshot(self, path):
        data = self.call("Page.captureScreenshot", {"format": "png"})["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def close(self):
        try:
            self.call("Browser.close", session=False, timeout=10)
        except SystemExit:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


def request(url, method="GET", body=None, token_header=None):
    """(status, body text) of one HTTP request."""
    data = body.encode() if isinstance(body, str) else body
    req = urllib.request.Request(url, data=data, method=method)
    if data is not None:
        req.add_header("Content-Type", "application/json")
    if token_header:
        req.add_header("X-Camplace-Token", token_header)
    try:
        with urllib.request.urlopen(req, timeout=30) as response:
            return response.status, response.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--camplace", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--cameras", required=True)
    parser.add_argument("--resolution", default="36x27x27")
    parser.add_argument("--out", required=True, help="work directory (recreated)")
    parser.add_argument("--artifacts", required=True, help="where the screenshots go")
    parser.add_argument("--moves", type=int, default=20, help="moves timed for the round trip")
    parser.add_argument("--chromium", default="chromium")
    args = parser.parse_args()
    if shutil.which(args.chromium) is None:
        fail(args.chromium + " not found (scripts/install_deps.sh installs Debian's chromium)")
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    os.makedirs(args.artifacts, exist_ok=True)
    saves = os.path.join(args.out, "saves")

    server = subprocess.Popen(
        [args.camplace, "serve", args.scene, "--cameras", args.cameras, "--resolution",
         args.resolution, "--port", "0", "--out", saves],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    url = None
    for line in server.stdout:
        print("serve: " + line.rstrip())
        if line.startswith("open "):
            url = line.split()[1]
            break
    if url is None:
        fail("camplace serve printed no URL:\n" + server.stderr.read())
    base, token = re.match(r"(http://[^/]+)/\?token=([0-9a-f]+)$", url).groups()
    browser = None
    try:
        # Refused requests, and the server keeps running.
        code, text = request(base + "/api/scene")
        print("no token: HTTP %d %s" % (code, text.strip()))
        if code != 403 or not text.startswith("error: "):
            fail("a request without the token got HTTP %d %r, not 403 with an error line" % (code, text))
        code, text = request(base + "/api/scene?token=" + "0" * 32)
        if code != 403:
            fail("a request with a wrong token got HTTP %d, not 403" % code)
        code, text = request(base + "/api/update", "POST", "{\"cameras\": [", token)
        print("malformed JSON: HTTP %d %s" % (code, text.strip()))
        if code != 400 or not text.startswith("error: request: not valid JSON"):
            fail("a malformed request got HTTP %d %r" % (code, text))
        with open(args.cameras) as f:
            cameras = json.load(f)["cameras"]
        bad = json.loads(json.dumps(cameras))
        bad[0]["yaw_deg"] = 190
        code, text = request(base + "/api/update", "POST", json.dumps({"cameras": bad}), token)
        bad_file = os.path.join(args.out, "bad.json")
        with open(bad_file, "w") as f:
            json.dump({"cameras": bad}, f)
        cli = subprocess.run([args.camplace, "evaluate", args.scene, "--cameras", bad_file],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        print("yaw 190: HTTP %d %s; the command line: %s" % (code, text.strip(), cli.stderr.strip()))
        cli_reason = cli.stderr.strip().replace(bad_file, "request")
        if code != 400 or text.strip() != cli_reason:
            fail("out-of-range request: HTTP %d %r, expected 400 %r" % (code, text, cli_reason))
        code, _ = request(base + "/api/view?state=0", token_header=token)
        if code != 200:
            fail("the server does not answer after the refused requests (HTTP %d)" % code)

        # The page.
        browser = Browser(args.chromium, os.path.join(args.out, "profile"))
        browser.open(url)
        s = browser.wait("the page to show the configuration", lambda s: s.get("ready"))
        if s["errors"]:
            fail("errors in the page: %s" % s["errors"])
        start = s["cameras"][0]
        print("loaded: Err %s, camera 0 at %s" % (s["err"], start["position"]))
        time.sleep(0.3)
        browser.screenshot(os.path.join(args.artifacts, "serve-before.png"))

        # Move camera 0 by (+2, 0, -0.5) m with the fields (Err changes), then time more moves.
        start_err = s["err"]
        target = [start["position"][0] + 2.0, start["position"][1], start["position"][2] - 0.5]

        def move(position):
            before = browser.status()["updates"]
            for axis, value in zip("xyz", position):
                browser.type_into("f-" + axis, repr(value))
            browser.click("apply")
            return browser.wait("the update after the move",
                                lambda s: s["updates"] > before and not s["pending"])

        s = move(target)
        got = s["cameras"][0]["position"]
        if any(abs(a - b) > 1e-9 for a, b in zip(got, target)) or s["cameras"][0]["snapped"]:
            fail("camera 0 is at %s (snapped: %r), sent to %s" % (got, s["cameras"][0]["snapped"], target))
        moved_err = s["err"]
        print("moved camera 0 to %s: Err %s (%s)" % (target, moved_err, s["errText"]))
        if moved_err == start_err:
            fail("the move left Err at %s" % moved_err)
        times, splits = [], []
        for i in range(args.moves):
            step = [target[0] + 0.02 * ((i % 5) + 1), target[1], target[2]]
            s = move(step)
            times.append(s["lastRoundTripMs"])
            splits.append(s["lastSplitMs"])
        s = move(target)
        if s["err"] != moved_err:
            fail("back at the same place, Err %s differs from %s" % (s["err"], moved_err))
        print("round trip at %s, %d moves (change sent -> frame drawn with the answer): median "
              "%.1f ms, min %.1f ms, max %.1f ms; medians of its parts: %s; load average %s"
              % (args.resolution, len(times), statistics.median(times), min(times), max(times),
                 ", ".join("%s %.1f ms" % (k, statistics.median(x[k] for x in splits))
                           for k in ("server", "transfer", "draw", "frame")),
                 open("/proc/loadavg").read().split()[0]))

        # Drag camera 0 along the gizmo's x arrow with real mouse events: x changes, y, z and
        # the angles stay, and each step of the drag is answered.
        centre = browser.js("camplacePlanner.project(%s)" % json.dumps(target))
        ahead = browser.js("camplacePlanner.project(%s)" % json.dumps([target[0] + 0.1] + target[1:]))
        direction = [ahead[0] - centre[0], ahead[1] - centre[1]]
        norm = (direction[0] ** 2 + direction[1] ** 2) ** 0.5
        direction = [direction[0] / norm, direction[1] / norm]
        handle = None
        # The gizmo draws the x arrow on the side of +x or of -x (it flips arrows that point
        # away from the viewer): look on both sides, nearest first.
        for t in [sign * r for r in range(8, 200, 4) for sign in (1, -1)]:
            point = [centre[0] + t * direction[0], centre[1] + t * direction[1]]
            browser.call("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": point[0], "y": point[1]})
            if browser.status().get("hoverAxis") == "X":
                handle = point
                break
        if handle is None:
            fail("no x arrow of the gizmo found along the x axis from %s" % centre)
        before = browser.status()["updates"]
        browser.call("Input.dispatchMouseEvent", {"type": "mousePressed", "x": handle[0],
                                                  "y": handle[1], "button": "left", "clickCount": 1})
        for k in range(1, 11):
            browser.call("Input.dispatchMouseEvent",
                         {"type": "mouseMoved", "x": handle[0] - 6 * k * direction[0],
                          "y": handle[1] - 6 * k * direction[1], "button": "left", "buttons": 1})
            time.sleep(0.03)
        end = [handle[0] - 60 * direction[0], handle[1] - 60 * direction[1]]
        browser.call("Input.dispatchMouseEvent", {"type": "mouseReleased", "x": end[0], "y": end[1],
                                                  "button": "left", "clickCount": 1})
        # The release's answer comes last (a drag sends one pose at a time, the latest).
        time.sleep(0.2)
        s = browser.wait("the answer to the release",
                         lambda s: s["updates"] > before + 1 and not s["pending"])
        dragged = s["cameras"][0]
        print("dragged camera 0 along x: %d answers, now at %s, Err %s"
              % (s["updates"] - before, dragged["position"], s["err"]))
        if not (dragged["position"][0] < target[0] - 0.05) or \
                any(abs(dragged["position"][i] - target[i]) > 1e-6 for i in (1, 2)) or \
                abs(dragged["yaw_deg"] - start["yaw_deg"]) > 1e-6 or \
                abs(dragged["pitch_deg"] - start["pitch_deg"]) > 1e-6:
            fail("the drag along the x arrow moved camera 0 from %s (yaw %s, pitch %s) to %s "
                 "(yaw %s, pitch %s)" % (target, start["yaw_deg"], start["pitch_deg"],
                                         dragged["position"], dragged["yaw_deg"],
                                         dragged["pitch_deg"]))
        time.sleep(0.3)
        browser.screenshot(os.path.join(args.artifacts, "serve-after.png"))

        # Turn it with the gizmo's rings: the position stays, the direction changes.
        browser.click("mode-rotate")
        position = dragged["position"]
        centre = browser.js("camplacePlanner.project(%s)" % json.dumps(position))
        handle = None
        for radius in range(30, 220, 6):
            for k in range(24):
                angle = 2 * math.pi * k / 24
                point = [centre[0] + radius * math.cos(angle), centre[1] + radius * math.sin(angle)]
                browser.call("Input.dispatchMouseEvent",
                             {"type": "mouseMoved", "x": point[0], "y": point[1]})
                axis = browser.status().get("hoverAxis")
                if axis in ("X", "Y", "Z"):
                    handle = (point, angle, axis)
                    break
            if handle:
                break
        if handle is None:
            fail("no ring of the rotation gizmo found around %s" % centre)
        point, angle, axis = handle
        before = browser.status()["updates"]
        browser.call("Input.dispatchMouseEvent", {"type": "mousePressed", "x": point[0],
                                                  "y": point[1], "button": "left", "clickCount": 1})
        tangent = [-math.sin(angle), math.cos(angle)]
        for k in range(1, 11):
            browser.call("Input.dispatchMouseEvent",
                         {"type": "mouseMoved", "x": point[0] + 5 * k * tangent[0],
                          "y": point[1] + 5 * k * tangent[1], "button": "left", "buttons": 1})
            time.sleep(0.03)
        browser.call("Input.dispatchMouseEvent",
                     {"type": "mouseReleased", "x": point[0] + 50 * tangent[0],
                      "y": point[1] + 50 * tangent[1], "button": "left", "clickCount": 1})
        time.sleep(0.2)
        s = browser.wait("the answer to the turn's release",
                         lambda s: s["updates"] > before + 1 and not s["pending"])
        turned = s["cameras"][0]
        print("turned camera 0 about the %s ring: yaw %.3f -> %.3f, pitch %.3f -> %.3f, at %s, Err %s"
              % (axis, dragged["yaw_deg"], turned["yaw_deg"], dragged["pitch_deg"],
                 turned["pitch_deg"], turned["position"], s["err"]))
        if any(abs(a - b) > 1e-9 for a, b in zip(turned["position"], position)) or \
                abs(turned["yaw_deg"] - dragged["yaw_deg"]) + \
                abs(turned["pitch_deg"] - dragged["pitch_deg"]) < 1.0:
            fail("the turn moved camera 0 or did not turn it: %s -> %s" % (dragged, turned))
        browser.click("mode-translate")
        moved_err = s["err"]

        # Save, and `camplace evaluate` of the saved file gives the Err shown.
        browser.type_into("save-name", "moved")
        browser.click("save")
        s = browser.wait("the save", lambda s: s.get("saved"))
        saved = s["saved"]["cameras_file"]
        evaluate = subprocess.run(
            [args.camplace, "evaluate", args.scene, "--cameras", saved, "--resolution",
             args.resolution, "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if evaluate.returncode != 0:
            fail("camplace evaluate of %s: %s" % (saved, evaluate.stderr))
        evaluated = json.loads(evaluate.stdout)["err"]
        printed = subprocess.run(
            [args.camplace, "evaluate", args.scene, "--cameras", saved, "--resolution",
             args.resolution], stdout=subprocess.PIPE, text=True).stdout
        err_line = re.search(r"^Err = ([0-9.]+) m²", printed, re.M).group(1)
        print("saved %s; camplace evaluate: Err %r (printed %s); the page shows %r (%s)"
              % (saved, evaluated, err_line, moved_err, s["errText"]))
        if evaluated != moved_err or s["errText"] != "Err = %s m²" % err_line:
            fail("the saved file evaluates to Err %r (%s), the page shows %r (%s)"
                 % (evaluated, err_line, moved_err, s["errText"]))

        # Check exactly: cancel the first, let the second finish; its exact Err is the one of
        # `camplace evaluate --pipeline both` of the saved file.
        browser.click("check-exact")
        s = browser.wait("the first exact state",
                         lambda s: s.get("job") and len(s["job"].get("states", [])) >= 1)
        browser.click("cancel")
        s = browser.wait("the cancelled exact check",
                         lambda s: s["job"].get("state") not in (None, "running"), timeout=60)
        if s["job"]["state"] != "cancelled" or len(s["job"]["result"]["states"]) >= 6:
            fail("the exact check ended with %s after %d states, not cancelled"
                 % (s["job"]["state"], len(s["job"]["result"]["states"])))
        print("check exactly cancelled after %d of 6 states" % len(s["job"]["result"]["states"]))
        browser.click("check-exact")
        browser.wait("the exact check to start", lambda s: s["job"].get("state") == "running")
        # Meanwhile the planner answers: the same place again, while the check runs.
        started = time.time()
        s = move(browser.status()["cameras"][0]["position"])
        answered = time.time() - started
        print("a move while the exact check runs (%s): answered in %.0f ms"
              % (s["job"].get("progress", {}).get("stage", "setting up"), 1000 * answered))
        if s["job"]["state"] != "running" or answered > 2.0 or s["err"] != moved_err:
            fail("a move during the exact check: job %s, answered in %.2f s, Err %s"
                 % (s["job"]["state"], answered, s["err"]))
        s = browser.wait("the exact check", lambda s: s["job"].get("state") == "finished"
                         and s["job"]["kind"] == "check exactly", timeout=120)
        exact = s["job"]["result"]
        both = subprocess.run(
            [args.camplace, "evaluate", args.scene, "--cameras", saved, "--resolution",
             args.resolution, "--pipeline", "both", "--json"], stdout=subprocess.PIPE, text=True)
        both = json.loads(both.stdout)
        print("check exactly: exact Err %r, voxel Err %r (%.1f s); camplace evaluate --pipeline "
              "both: exact %r, voxel %r" % (exact["exact_err"], exact["voxel_err"],
                                            exact["seconds"], both["exact"]["err"],
                                            both["voxel"]["err"]))
        if abs(exact["exact_err"] - both["exact"]["err"]) > 1e-12 or \
                exact["voxel_err"] != both["voxel"]["err"]:
            fail("check exactly differs from camplace evaluate --pipeline both")
        for mine, theirs in zip(exact["states"], both["exact"]["states"]):
            if abs(mine["d_model_exact"] - theirs["d_model"]) > 1e-12:
                fail("state %s: exact d_model %r, evaluate %r" % (mine, mine["d_model_exact"],
                                                                  theirs["d_model"]))

        # Optimise from here, follow it, then cancel.
        browser.type_into("opt-seconds", "60")
        browser.click("optimise")
        s = browser.wait("optimisation progress",
                         lambda s: s.get("job") and s["job"]["kind"] == "optimise" and
                         s["job"].get("progress", {}).get("evaluations", 0) >= 100)
        print("optimising: %s" % json.dumps(s["job"]["progress"]))
        started = time.time()
        browser.click("cancel")
        s = browser.wait("the cancelled optimisation",
                         lambda s: s["job"].get("state") not in (None, "running"), timeout=30)
        result = s["job"]["result"]
        print("optimisation %s after %.2f s: %d evaluations, Err %s -> %s (cancel took %.2f s)"
              % (result["status"], result["seconds"], result["evaluations"], result["start_err"],
                 result["err"], time.time() - started))
        if result["status"] != "cancelled" or result["stop_reason"] != "interrupted":
            fail("the optimisation ended with %s (%s), not cancelled" % (result["status"], result["stop_reason"]))
        if not result["err"] <= result["start_err"]:
            fail("the optimisation made Err worse: %s -> %s" % (result["start_err"], result["err"]))
        s = browser.wait("the page showing the optimiser's result",
                         lambda s: s["err"] == result["err"])
        code, _ = request(base + "/api/view?state=0", token_header=token)
        if code != 200:
            fail("the server does not answer after the cancel (HTTP %d)" % code)

        # Undo goes back to the saved configuration: past the optimiser's result when it found a
        # better one (an undo step), then past one more move.
        def undo():
            before = browser.status()["updates"]
            browser.click("undo")
            return browser.wait("the undo", lambda s: s["updates"] > before and not s["pending"])

        if browser.status()["dirty"]:
            print("the optimiser's result is an undo step")
            undo()
        elsewhere = browser.status()["cameras"][0]["position"]
        s = move([elsewhere[0] - 0.3, elsewhere[1] + 0.2, elsewhere[2]])
        if not s["dirty"] or s["undo"] < 1:
            fail("a move after saving: dirty %s, %s undo steps" % (s["dirty"], s["undo"]))
        s = undo()
        with open(saved) as f:
            saved_cameras = json.load(f)["cameras"]
        if s["err"] != moved_err or s["dirty"]:
            fail("after undo Err %s (dirty %s), the saved configuration has %s"
                 % (s["err"], s["dirty"], moved_err))
        for a, b in zip(s["cameras"], saved_cameras):
            if a["position"] != b["position"] or a["yaw_deg"] != b["yaw_deg"]:
                fail("after undo camera %s differs from the saved %s" % (a, b))
        s = browser.status()
        if s["errors"]:
            fail("errors in the page: %s" % s["errors"])
        print("undo: back to the saved configuration, Err %s" % s["err"])

        # Add a camera of the scene's model, then remove it again.
        before = s["updates"]
        browser.click("add")
        s = browser.wait("the added camera", lambda s: s["updates"] > before and not s["pending"])
        if len(s["cameras"]) != 7:
            fail("after add camera the page shows %d cameras" % len(s["cameras"]))
        added_err = s["err"]
        if s["selected"] != 6:
            fail("the added camera is not the selected one (camera %s is)" % s["selected"])
        before = s["updates"]
        browser.click("remove")
        s = browser.wait("the removed camera", lambda s: s["updates"] > before and not s["pending"])
        if len(s["cameras"]) != 6 or s["err"] != moved_err or s["dirty"]:
            fail("after removing the added camera: %d cameras, Err %s, dirty %s"
                 % (len(s["cameras"]), s["err"], s["dirty"]))
        print("added camera 6 (Err %s), removed it (Err %s)" % (added_err, s["err"]))
        if s["errors"]:
            fail("errors in the page: %s" % s["errors"])
    finally:
        if browser:
            browser.close()
        if server.poll() is None:
            server.send_signal(signal.SIGINT)
        try:
            out, err = server.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            fail("camplace serve did not stop within 30 s of SIGINT")
    print("serve: " + out.strip().replace("\n", "\nserve: "))
    if err.strip():
        print("serve stderr: " + err.strip())
    if server.returncode != 0 or "no unsaved changes" not in out:
        fail("camplace serve ended with %d after SIGINT:\n%s%s" % (server.returncode, out, err))
    print("screenshots: %s/serve-before.png, serve-after.png" % args.artifacts)
    print("PASS")


if __name__ == "__main__":
    main()
