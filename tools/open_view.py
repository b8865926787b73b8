#!/usr/bin/env python3
"""open_view.py PAGE.html [--hash PARAMS] [--screenshot PNG] [--size WxH] [--repeat N]

Opens a page that `noether view` wrote in headless Chromium (Debian's chromium, software WebGL)
and prints what the page reports: the frame shown, its time, and how long the page took to be
ready (from the start of its loading to its first picture drawn; the median of --repeat loads).
Exits 1 when the page reports a console error or warning. --screenshot saves the picture
(--size: the window's size, default 1280x800). PARAMS are the page's address parameters
(docs/visualisation.md, "Parameters"), e.g. --hash 'frame=100&view=frame:alpha'.
"""
import argparse
import html
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

CHROMIUM = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--hide-scrollbars", "--mute-audio", "--no-first-run"]


def browse(page, params="", screenshot=None, size=(1280, 800), profile=None):
    """The page's status (the JSON it reports in #noether-status) after it loaded with `params`;
    with `screenshot`, also saves the window's picture there. Raises RuntimeError when Chromium
    fails or the page reports nothing."""
    with tempfile.TemporaryDirectory() as scratch:
        args = CHROMIUM + [f"--user-data-dir={profile or scratch}", f"--window-size={size[0]},{size[1]}"]
        url = "file://" + os.path.abspath(page) + ("#" + params if params else "")
        p = subprocess.run(args + ["--dump-dom", url], capture_output=True, text=True, timeout=120)
        m = re.search(r'<pre id="noether-status" hidden="">(.*?)</pre>', p.stdout, re.S)
        if p.returncode != 0 or not m:
            raise RuntimeError(f"{page}: chromium exit {p.returncode}, no status from the page\n{p.stderr[-2000:]}")
        status = json.loads(html.unescape(m.group(1)))
        if screenshot:
            p = subprocess.run(args + [f"--screenshot={os.path.abspath(screenshot)}", url], capture_output=True,
                               text=True, timeout=120)
            if p.returncode != 0 or not os.path.exists(screenshot):
                raise RuntimeError(f"{page}: chromium could not take a screenshot\n{p.stderr[-2000:]}")
    return status


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[1])
    parser.add_argument("page")
    parser.add_argument("--hash", default="", help="the page's address parameters")
    parser.add_argument("--screenshot", help="save the picture here (PNG)")
    parser.add_argument("--size", default="1280x800", help="the window's size, WxH")
    parser.add_argument("--repeat", type=int, default=1, help="load the page N times; print the median")
    a = parser.parse_args()
    size = tuple(int(v) for v in a.size.split("x"))
    loads = []
    for i in range(a.repeat):
        status = browse(a.page, a.hash, a.screenshot if i == 0 else None, size)
        loads.append(status.get("load_ms", float("nan")))
    problems = status["errors"] + status["warnings"]
    print(f"page            {a.page} ({os.path.getsize(a.page) / 1e6:.1f} MB)")
    print(f"frames shown    {status.get('frames_shown')}, showing frame {status.get('file_frame')} of the file "
          f"at t = {status.get('time')}")
    print(f"ready after     {statistics.median(loads):.0f} ms (median of {len(loads)} loads)")
    if a.screenshot:
        print(f"screenshot      {a.screenshot}")
    if not status["ready"] or problems:
        print("the page reported:", *problems, sep="\n  ", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
