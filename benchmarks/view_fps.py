"""Frames per second of the browser view in headless Chromium, and the view's cost to a running simulation.

Not a YADE script: it drives Debian's chromium through selenium (``granum[view]`` and ``selenium``). For each
size, ``n`` spheres settle in a facet box (tutorial 02's engines); the page is loaded and the camera turned
for ``BENCH_SECONDS`` seconds, one turn per animation frame: the fps is the number of frames drawn per second
(vtk.js on Chromium's software WebGL when there is no GPU). On a machine shared with other jobs the fps
depends on the load, so the CPU time all of Chromium's processes spent per frame is reported too
(``chromium_cpu_ms``, with ``fps_one_core``, its inverse: the frame rate with one core for Chromium alone;
``gpu_process_ms`` and ``renderer_ms`` its parts in Chromium's GPU process, where SwiftShader draws, and in the
page's renderer, where the JavaScript runs),
and the load average at the time. Each size is measured with the page's occlusion culling (``granum-view.js``:
on software WebGL the spheres hidden behind others are not drawn) off, then on ``BENCH_REPEAT`` times in a row
(one run's frame rate moved by 10-20 % on a shared 2-core machine; a ``view_fps_runs`` line gives the
smallest, median and largest), with the spheres the last frame drew and the JavaScript time culling took per
frame (``culling_js_ms``, part of ``chromium_cpu_ms``). ``frames_culled`` (culling on) counts the frames the
page drew anew, out of the animation frames counted: equal when each turn is drawn (with Chromium's software
compositor, ``--disable-gpu-compositing``, animation frames ran at twice the drawing rate, so the fps would
read twice too high). Then the simulation runs ``BENCH_STEPS`` steps with the page open; ``server_share`` is the
time spent taking frames between compiled chunks and publishing them to the page, over the run's time (the
view's server-side cost, target <= 5 %; ``seconds_with_view`` also includes Chromium drawing on the same
cores).

    python benchmarks/view_fps.py   # BENCH_SIZES=10000,100000 BENCH_SECONDS=10 BENCH_REPEAT=3 BENCH_STEPS=200
"""

from __future__ import annotations

import os
import shutil
import time

TURN = """
const done = arguments[arguments.length - 1];
const view = trame.refs.view;
const cam = view.getCamera();
const seconds = arguments[0];
let frames = 0;
const t0 = performance.now();
function step(now) {
  if (now - t0 > seconds * 1000) { done([frames, (now - t0) / 1000]); return; }
  const a = frames * 0.05, r = Math.hypot(cam.position[0] - cam.focalPoint[0], cam.position[2] - cam.focalPoint[2]);
  const f = cam.focalPoint;
  view.setCamera({position: [f[0] + r * Math.sin(a), cam.position[1], f[2] + r * Math.cos(a)]});
  frames += 1;
  requestAnimationFrame(step);
}
requestAnimationFrame(step);
"""


def scene(n: int) -> None:
    from granum.yade import O, geom, pack

    O.reset()
    side = round(n ** (1 / 3))
    r = 0.5 / side
    O.bodies.append(geom.facetBox((0.5, 0.5, 0.5), (0.5, 0.5, 0.5), wallMask=31))
    O.bodies.append(pack.regularOrtho(pack.inAlignedBox((0, 0, 0), (1, 1, 1)), radius=r * 0.9, gap=r * 0.2))
    from granum.yade import (
        Bo1_Facet_Aabb,
        Bo1_Sphere_Aabb,
        ForceResetter,
        Ig2_Facet_Sphere_ScGeom,
        Ig2_Sphere_Sphere_ScGeom,
        InsertionSortCollider,
        InteractionLoop,
        Ip2_FrictMat_FrictMat_FrictPhys,
        Law2_ScGeom_FrictPhys_CundallStrack,
        NewtonIntegrator,
        utils,
    )

    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.4)]
    O.dt = 0.5 * utils.PWaveTimeStep()


def chromium_cpu_seconds(driver) -> dict[str, float]:
    """CPU time [s] (user + system) used so far by the processes of the browser chromedriver started, by the
    kind Chromium gives a process on its command line (``gpu-process``: WebGL, drawn by SwiftShader without a
    GPU; ``renderer``: the page's JavaScript; ``browser``: the rest)."""
    import psutil

    totals: dict[str, float] = {}
    for p in psutil.Process(driver.service.process.pid).children(recursive=True):
        try:
            t = p.cpu_times()
            kind = next((a.split("=", 1)[1] for a in p.cmdline() if a.startswith("--type=")), "browser")
        except psutil.NoSuchProcess:
            continue
        totals[kind] = totals.get(kind, 0.0) + t.user + t.system
    return totals


def main() -> None:
    from selenium import webdriver

    from granum.yade import O, view

    sizes = [int(x) for x in os.environ.get("BENCH_SIZES", "10000,100000").split(",")]
    seconds = float(os.environ.get("BENCH_SECONDS", "10"))
    repeat = int(os.environ.get("BENCH_REPEAT", "3"))
    if repeat < 1:
        raise SystemExit(f"view_fps: BENCH_REPEAT={repeat}: the runs with culling must be at least 1")
    steps = int(os.environ.get("BENCH_STEPS", "200"))
    options = webdriver.ChromeOptions()
    for arg in ("--headless=new", "--no-sandbox", "--window-size=1000,700", "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader", *os.environ.get("BENCH_CHROME_FLAGS", "").split()):
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options,
                              service=webdriver.ChromeService(executable_path=shutil.which("chromedriver")))
    driver.set_script_timeout(seconds + 120)
    view.allow()
    for n in sizes:
        scene(n)
        O.run(1, True)          # compiles (or loads) the kernels before anything is timed
        t0 = time.perf_counter()
        O.run(steps, True)
        bare = time.perf_counter() - t0
        session = view.open_view(open_browser=False)
        session._idle_key = None
        driver.get(session.url)
        spheres = len(O.bodies) - 12
        end = time.monotonic() + 120
        while time.monotonic() < end and f"({spheres} spheres)" not in driver.page_source:
            time.sleep(0.2)
        time.sleep(2)
        on_fps = []
        for culling in ("off",) + ("on",) * repeat:   # the page's occlusion culling (software WebGL only)
            driver.execute_script(f"window.granum_view.setCulling({'true' if culling == 'on' else 'false'});"
                                  "window.granum_view.cullingMs = 0; window.granum_view.framesCulled = 0;")
            time.sleep(1)
            cpu0 = chromium_cpu_seconds(driver)
            drawn, elapsed = driver.execute_async_script(TURN, seconds)
            cpu1 = chromium_cpu_seconds(driver)
            per_frame = {kind: (cpu1[kind] - cpu0.get(kind, 0.0)) / max(drawn, 1) for kind in cpu1}
            cpu_per_frame = sum(per_frame.values())
            shown, cull_ms, culled = driver.execute_script(
                "const v = window.granum_view; return [v.spheresDrawn, v.cullingMs, v.framesCulled];")
            print(f"BENCH name=view_fps spheres={spheres} culling={culling} fps={drawn / elapsed:.3g} "
                  f"chromium_cpu_ms={cpu_per_frame * 1e3:.4g} fps_one_core={1 / cpu_per_frame:.3g} "
                  f"gpu_process_ms={per_frame.get('gpu-process', 0.0) * 1e3:.4g} "
                  f"renderer_ms={per_frame.get('renderer', 0.0) * 1e3:.4g} "
                  f"culling_js_ms={cull_ms / max(drawn, 1):.3g} frames_culled={culled}/{drawn} "
                  f"spheres_drawn_last={shown} "
                  f"load_average={os.getloadavg()[0]:.3g}", flush=True)
            if culling == "on":
                on_fps.append(drawn / elapsed)
        on_fps.sort()
        print(f"BENCH name=view_fps_runs spheres={spheres} culling=on runs={len(on_fps)} fps_min={on_fps[0]:.3g} "
              f"fps_median={on_fps[len(on_fps) // 2]:.3g} fps_max={on_fps[-1]:.3g}", flush=True)
        session.hook_seconds = session.publish_seconds = 0.0
        taken = session.frames_taken
        t0 = time.perf_counter()
        O.run(steps, True)
        viewed = time.perf_counter() - t0
        share = (session.hook_seconds + session.publish_seconds) / viewed
        print(f"BENCH name=view_server spheres={spheres} steps={steps} seconds_without_view={bare:.4g} "
              f"seconds_with_view={viewed:.4g} server_share={share:.2%} hook_s={session.hook_seconds:.3g} "
              f"publish_s={session.publish_seconds:.3g} frames={session.frames_taken - taken} "
              f"load_average={os.getloadavg()[0]:.3g}", flush=True)
        view.close_view()
    driver.quit()


if __name__ == "__main__":
    main()
