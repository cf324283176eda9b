"""tests/cli/animate_browser.py: the animation page in a real browser (headless Chromium).

Run by animate_test.sh with the page's directory: loads page.html at set times and a set camera,
unlit (#flat=1), takes screenshots, and checks that each link's pixels (of its known colour) sit
where forward kinematics puts the link, projected by a pinhole camera computed here. The
reference positions come from the run's CSV joint angles and the planar arm's geometry written
by hand below (not from varsym's kinematics). Also: the page with a missing mesh still renders
(data-ready) and shows its warning. Prints one line per check; exits 1 on a failure, 77 when
Chromium or matplotlib is missing (skipped)."""

import csv
import math
import os
import re
import shutil
import subprocess
import sys

W, H, FOV = 800, 600, 40.0
EYE, TARGET = (0.3, -3.2, 0.2), (0.1, 0.0, -0.35)
L1, L2 = 0.5, 0.4  # the arm's link lengths (animate_test.sh writes the URDF)

failures = 0


def check(ok, what):
    global failures
    print(("ok: " if ok else "FAIL: ") + what)
    failures += 0 if ok else 1


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


def browser(exe, work, url, out=None):
    """A screenshot of url to out, or the DOM after the scripts ran (out None)."""
    args = [exe, "--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--hide-scrollbars", "--force-device-scale-factor=1",
            "--no-first-run", "--disable-extensions", f"--user-data-dir={work}/profile",
            f"--window-size={W},{H}", "--virtual-time-budget=4000"]
    args += [f"--screenshot={out}"] if out else ["--dump-dom"]
    r = subprocess.run(args + [url], capture_output=True, text=True, timeout=120)
    return r.stdout


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def project(p):
    """Pixel (x, y) of world point p: a camera at EYE looking at TARGET with z up, vertical
    field of view FOV, image W × H (three.js's PerspectiveCamera and lookAt)."""
    back = unit(sub(EYE, TARGET))  # the camera's +z
    right = unit(cross([0.0, 0.0, 1.0], back))
    up = cross(back, right)
    d = sub(p, EYE)
    x, y, z = dot(d, right), dot(d, up), dot(d, back)
    f = 1.0 / math.tan(math.radians(FOV) / 2)
    ndc_x, ndc_y = f * x / (-z) / (W / H), f * y / (-z)
    return (ndc_x + 1) / 2 * W, (1 - ndc_y) / 2 * H


def arm(q1, q2):
    """The centres of links 1 and 2 of the planar arm (joints about +y: x turns to −z)."""
    e1 = (math.cos(q1), 0.0, -math.sin(q1))
    e2 = (math.cos(q1 + q2), 0.0, -math.sin(q1 + q2))
    c1 = [L1 / 2 * x for x in e1]
    c2 = [L1 * a + L2 / 2 * b for a, b in zip(e1, e2)]
    return c1, c2


def pixels(png, rgb, tol=0.08):
    import numpy as np  # noqa: PLC0415
    img = png[:, :, :3]
    mask = np.all(np.abs(img - np.array(rgb)) < tol, axis=2)
    ys, xs = np.nonzero(mask)
    return len(xs), (xs.mean() + 0.5 if len(xs) else math.nan), (ys.mean() + 0.5 if len(ys) else math.nan)


def main():
    work = sys.argv[1]
    exe = chromium()
    if exe is None:
        print("SKIP: no Chromium (apt-get install chromium): the browser checks did not run")
        return 77
    try:
        import matplotlib.image  # noqa: PLC0415
    except ImportError:
        print("SKIP: no matplotlib to read the screenshots (python3-matplotlib)")
        return 77
    rows = {round(float(r["t"]), 9): r for r in csv.DictReader(open(f"{work}/arm.csv"))}
    page = "file://" + os.path.abspath(f"{work}/arm.html")
    cam = ",".join(str(x) for x in EYE + TARGET)
    dom = browser(exe, work, page)
    check('data-ready="1"' in dom, "the page with a missing mesh renders (data-ready)")
    shown = re.search(r'<div id="warnings"><div>[^<]*link l3: mesh [^<]*missing_pkg[^<]*not found', dom)
    check(shown is not None, "the page shows the missing mesh's warning (in its warnings box)")
    centres = {}
    for t in (0.0, 0.5, 1.0):
        out = f"{work}/shot_{t}.png"
        browser(exe, work, f"{page}#t={t}&flat=1&ui=0&fov={FOV}&cam={cam}", out)
        if not os.path.exists(out):
            check(False, f"screenshot at t = {t}")
            continue
        png = matplotlib.image.imread(out)
        check(png.shape[0] == H and png.shape[1] == W, f"screenshot {W}x{H} at t = {t}")
        r = rows[round(t, 9)]
        c1, c2 = arm(float(r["q_j1"]), float(r["q_j2"]))
        for name, rgb, centre in (("link 1 (red box)", (1, 0, 0), c1),
                                  ("link 2 (blue STL mesh)", (0, 0, 1), c2)):
            n, x, y = pixels(png, rgb)
            px, py = project(centre)
            check(40 < px < W - 40 and 40 < py < H - 40, f"t = {t}: {name} is in the picture")
            miss = math.hypot(x - px, y - py)
            centres[(name, t)] = (px, py, x, y)
            check(n > 200 and miss < 3.0,
                  f"t = {t}: {name}: {n} pixels, centroid ({x:.1f}, {y:.1f}) vs forward "
                  f"kinematics ({px:.1f}, {py:.1f}): {miss:.2f} px apart")
        n, _, _ = pixels(png, (1.0, 0.6, 0.1))
        check(n > 30, f"t = {t}: link 3 (mesh missing) drawn as a capsule: {n} amber pixels")
    # Negative control: the link moved between t = 0 and 1, and each shot matches its own
    # time's kinematics, not the other's.
    a, b = centres.get(("link 1 (red box)", 0.0)), centres.get(("link 1 (red box)", 1.0))
    if a and b:
        moved = math.hypot(a[0] - b[0], a[1] - b[1])
        off = math.hypot(b[2] - a[0], b[3] - a[1])
        check(moved > 20 and off > 10,
              f"negative control: link 1 moved {moved:.0f} px from t = 0 to 1; the t = 1 shot is "
              f"{off:.0f} px from where t = 0 would put it")
    pendulum(exe, work, cam)
    return 1 if failures else 0


def pendulum(exe, work, cam):
    """A built-in model's figure: the spherical pendulum's red bob where its CSV's q (x, y, z)
    puts it, projected by the same camera."""
    import matplotlib.image  # noqa: PLC0415
    rows = {round(float(r["t"]), 9): r for r in csv.DictReader(open(f"{work}/pend.csv"))}
    page = "file://" + os.path.abspath(f"{work}/pend.html")
    seen = []
    for t in (0.0, 0.5, 1.0):
        out = f"{work}/pend_{t}.png"
        browser(exe, work, f"{page}#t={t}&flat=1&ui=0&fov={FOV}&cam={cam}", out)
        if not os.path.exists(out):
            check(False, f"pendulum screenshot at t = {t}")
            continue
        r = rows[round(t, 9)]
        px, py = project([float(r["q_1"]), float(r["q_2"]), float(r["q_3"])])
        n, x, y = pixels(matplotlib.image.imread(out), (0.85, 0.15, 0.15), tol=0.03)
        miss = math.hypot(x - px, y - py)
        seen.append((px, py))
        check(n > 200 and miss < 3.0,
              f"t = {t}: the spherical pendulum's bob: {n} pixels, centroid ({x:.1f}, {y:.1f}) "
              f"vs q ({px:.1f}, {py:.1f}): {miss:.2f} px apart")
    if len(seen) == 3:
        moved = math.hypot(seen[0][0] - seen[2][0], seen[0][1] - seen[2][1])
        check(moved > 20, f"negative control: the bob moved {moved:.0f} px from t = 0 to 1")


if __name__ == "__main__":
    sys.exit(main())
