#!/usr/bin/env python3
"""The reports in a real browser (issue 22, item 1): each report.html given is opened in headless
Chromium, which dumps its DOM and takes screenshots; the check asserts that
  - the DOM holds every figure of the directory as an inline <svg>, each with its caption, and
    every table has rows;
  - nothing in the DOM refers outside the page (no src, href, url( or @import; the only
    address is the SVG namespace);
  - every figure renders: a page of that figure alone, screenshot by Chromium, is not blank
    (at least 2 % of its pixels not white, and several colours);
  - the whole page renders (its first screen is not blank);
  - the page opens with its answer (issue 42, item 6): before any figure or table of a file.
Screenshots are kept in OUT (one per report, one per figure).

Usage: check_reports.py CHROMIUM OUT REPORT_DIR...
"""
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--hide-scrollbars",
]


def chromium_once(exe, args, url):
    with tempfile.TemporaryDirectory() as profile:
        try:
            return subprocess.run([exe, *FLAGS, f"--user-data-dir={profile}", *args, url],
                                  capture_output=True, text=True, timeout=120)
        except subprocess.TimeoutExpired as e:
            return subprocess.CompletedProcess(e.cmd, -1, e.stdout or "", f"timed out: {e}")


def chromium(exe, args, url, done):
    """Chromium on `url`, again (up to 3 times) while `done(result)` is false: a headless
    Chromium on a loaded CI machine now and then exits before it has printed the DOM or written
    the screenshot (CI stop 34: an empty DOM, the same report whole on this machine). A browser
    that never delivers fails the check with its own words, never a report that is blank."""
    for attempt in range(3):
        r = chromium_once(exe, args, url)
        if done(r):
            return r
        tail = (r.stderr or "")[-1500:]
        print(f"chromium attempt {attempt + 1} on {url} ({' '.join(args)}) delivered nothing "
              f"(exit {r.returncode}); its last words:\n{tail}", file=sys.stderr)
    sys.exit(f"chromium never delivered {' '.join(args)} for {url}")


def dump_dom(exe, url):
    return chromium(exe, ["--dump-dom"], url, lambda r: "</html>" in (r.stdout or "")).stdout


def screenshot(exe, shot, size, url):
    if os.path.exists(shot):
        os.remove(shot)
    chromium(exe, [f"--screenshot={shot}", f"--window-size={size}"], url,
             lambda r: os.path.exists(shot) and os.path.getsize(shot) > 0)


def png_pixels(path):
    """(width, height, rows of bytes, bytes per pixel) of an 8-bit RGB or RGBA PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    pos, idat, w = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), f"{path}: depth {depth}, colour type {colour}"
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, rows, bpp


def not_blank(path, what):
    w, h, rows, bpp = png_pixels(path)
    inked, colours = 0, set()
    for r in rows[::2]:
        for x in range(0, w * bpp, bpp * 2):
            px = r[x:x + 3]
            colours.add(px)
            if px != b"\xff\xff\xff":
                inked += 1
    share = inked / ((h + 1) // 2 * ((w + 1) // 2))
    assert share > 0.02 and len(colours) > 8, f"{what}: blank ({share:.3%} inked, {len(colours)} colours)"
    return share


def main():
    exe, out, dirs = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.makedirs(out, exist_ok=True)
    for d in dirs:
        d = os.path.abspath(d)
        name = os.path.basename(d)
        page = os.path.join(d, "report.html")
        url = "file://" + page
        svgs = sorted(f for f in os.listdir(d) if f.endswith(".svg"))
        dom = dump_dom(exe, url)
        assert dom.count("<svg") == len(svgs), f"{name}: {dom.count('<svg')} svg in the DOM, {len(svgs)} figures"
        assert dom.count("<figcaption>") == len(svgs), f"{name}: captions"
        for body in dom.split("<tbody>")[1:]:
            assert "<tr>" in body.split("</tbody>")[0], f"{name}: a table without rows"
        for bad in ("src=", "href=", "url(", "@import"):
            assert bad not in dom, f"{name}: {bad} in the page"
        # Every page opens with its answer (issue 42, item 6): the answer's heading comes before
        # the first figure and before the first table of a file.
        answer = dom.find('id="answer"')
        assert answer >= 0, f"{name}: no answer section"
        first_svg = dom.find("<svg")
        assert first_svg < 0 or answer < first_svg, f"{name}: a figure before the answer"
        first_file = min([i for i in (dom.find("<h2>The run</h2>"), dom.find(".csv</h2>")) if i >= 0],
                         default=len(dom))
        assert answer < first_file, f"{name}: a table of the set-up or a file before the answer"
        # Every page: the command line, and the case with each value's source.
        assert "command line not recorded" not in dom, f"{name}: no command line"
        assert "<caption>Provenance</caption>" in dom, f"{name}: no provenance table"
        if name == "run":
            # The acceptance criteria: the system assessed, and rows with their sources.
            assert "Supply system: ac" in dom and "<td>speed-ratio</td>" in dom, f"{name}: assessment"
        for m in re.finditer(r"https?://[^\"'\s<>)]+", dom):
            assert m.group(0).startswith("http://www.w3.org/2000/svg"), f"{name}: address {m.group(0)}"
        shot = os.path.join(out, f"{name}-report.png")
        screenshot(exe, shot, "1300,1600", url)
        share = not_blank(shot, f"{name} report")
        print(f"{name}: {len(svgs)} figures, {dom.count('<table>')} tables; first screen {share:.1%} inked -> {shot}")
        # Each figure alone, as the report has it (its style, its caption).
        style = re.search(r"<style>.*?</style>", open(page).read(), re.S).group(0)
        html = open(page).read()
        for i, fig in enumerate(re.findall(r"<figure id=\"[^\"]*\">.*?</figure>", html, re.S)):
            one = os.path.join(out, f"{name}-figure{i}.html")
            open(one, "w").write(f"<!DOCTYPE html><html><head><meta charset=\"utf-8\">{style}</head><body>{fig}</body></html>")
            shot = os.path.join(out, f"{name}-figure{i}.png")
            screenshot(exe, shot, "1300,900", "file://" + one)
            share = not_blank(shot, f"{name} figure {i}")
            os.remove(one)
            print(f"  figure {i}: {share:.1%} inked -> {shot}")
    print("reports render in Chromium: ok")


if __name__ == "__main__":
    main()
