"""Running vmas: the binary run as a subprocess (wall time, on request its own peak memory, killed
on a timeout), `vmas skeletonize --json` with the checks of the medial mesh it wrote, `vmas eval
--json` and the parsing of both summaries; and the vmas Python module (use_vmas), through which
the meshes and medial meshes are read."""

import json
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np

import vmas_files

vmas = None  # vmas' Python module, the one built with --vmas: set by use_vmas()


def use_vmas(binary):
    """Imports the Python module built with the vmas binary `binary` (see vmas_files)."""
    global vmas
    vmas = vmas_files.import_vmas(binary, "bench")


# Runs whose memory is measured go through this launcher, a fresh interpreter of a few MB (-I -S:
# no site packages). Linux counts in a process's ru_maxrss the resident memory of the process
# it was forked from (kept at exec; with the vfork of subprocess, that process's peak), so vmas
# started straight from the bench would report the bench's numpy arrays whenever they are the
# larger. The launcher forks and execs the command, reaps it with os.wait4 (the command's own
# rusage), writes "ru_maxrss_kb seconds" to the file argv[1] and exits as the command did; when
# it is terminated (timeout) it kills the command first.
MEASURE = r"""
import os, signal, sys, time
report, command = sys.argv[1], sys.argv[2:]
child = 0
def stop(signum, frame):
    if child:
        os.kill(child, signal.SIGKILL)
    else:
        os._exit(128 + signum)
signal.signal(signal.SIGTERM, stop)
signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops the command, which is reaped
signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM})
start = time.perf_counter()
child = os.fork()
if child == 0:
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGTERM})
    try:
        os.execvp(command[0], command)
    except OSError as e:
        os.write(2, f"cannot run {command[0]}: {e}\n".encode())
        os._exit(127)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGTERM})
_, status, usage = os.wait4(child, 0)
with open(report, "w") as f:
    f.write(f"{usage.ru_maxrss} {time.perf_counter() - start!r}\n")
code = os.waitstatus_to_exitcode(status)
if code < 0:  # die of the command's signal
    if -code != signal.SIGKILL:
        signal.signal(-code, signal.SIG_DFL)
    os.kill(os.getpid(), -code)
sys.exit(code if code >= 0 else 128 - code)
"""
KILL_GRACE_S = 30  # after a timeout: seconds between SIGTERM and SIGKILL


def run(command, timeout, memory=False):
    """Runs a command; returns dict(ok, seconds, stdout, stderr, returncode, error, command).
    memory=True runs it through MEASURE and adds peak_rss_kb, the command's own peak resident
    set size (None if unknown); seconds is then the command's own wall time."""
    argv, report = command, None
    if memory:
        fd, report = tempfile.mkstemp(prefix="bench-rusage-", suffix=".txt")
        os.close(fd)
        argv = [sys.executable, "-I", "-S", "-c", MEASURE, report] + list(command)
    result = {"ok": False, "seconds": None, "returncode": None, "stdout": "", "stderr": "",
              "error": None, "command": command}
    start = time.perf_counter()
    try:
        with subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) as proc:
            try:
                result["stdout"], result["stderr"] = proc.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                result["error"] = f"timeout after {timeout:g} s"
                proc.terminate()  # MEASURE kills the command, then exits
                try:
                    result["stdout"], result["stderr"] = proc.communicate(timeout=KILL_GRACE_S)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    result["stdout"], result["stderr"] = proc.communicate()
            except BaseException:  # e.g. KeyboardInterrupt: stop the command too
                if memory:
                    proc.terminate()  # MEASURE kills the command, reports, exits
                    proc.wait()
                else:
                    proc.kill()
                raise
    except OSError as e:
        result["error"] = str(e)
    finally:
        result["seconds"] = time.perf_counter() - start
        if memory:
            result["peak_rss_kb"] = None
            try:
                with open(report, encoding="utf-8") as f:
                    rss, seconds = f.read().split()
                result["peak_rss_kb"], result["seconds"] = int(rss), float(seconds)
            except (OSError, ValueError):
                pass  # the launcher did not finish: outer time, no memory
            os.remove(report)
    if result["error"]:
        return result
    result["returncode"] = proc.returncode
    result["ok"] = proc.returncode == 0
    if proc.returncode != 0:
        lines = [l.strip() for l in (result["stderr"] + "\n" + result["stdout"]).splitlines()
                 if l.strip()]
        if proc.returncode < 0:
            result["error"] = f"killed by signal {-proc.returncode}"
            if lines:
                result["error"] += ": " + lines[-1]
        else:
            result["error"] = f"exit {proc.returncode}: " + (lines[-1] if lines else "no message")
    return result


def parse_skeletonize_json(stdout):
    """Fields of the summary that `vmas skeletonize --json` prints (kept whole as "summary"):
    counts, iterations, thinning ({applied, points, voxel_percent}: the points that took part in
    the run), times, the noise estimate and the skeleton's connected components."""
    data = json.loads(stdout.strip().splitlines()[-1])
    stages = dict(data.get("seconds") or {})
    info = {"summary": data, "spheres": data.get("spheres"), "edges": data.get("edges"),
            "faces": data.get("medial_faces"), "iterations": data.get("iterations"),
            "thinning": data.get("thinning"), "vmas_total_s": stages.pop("total", None),
            "stages_s": stages}
    noise = data.get("noise") or {}
    if noise.get("measured"):
        info["noise_percent"] = noise.get("deviation_percent")
    info["components"] = (data.get("components") or {}).get("skeleton")
    return info


def parse_eval(stdout):
    """ε and the one-sided figures in % of the diagonal from `vmas eval --json` output (the keys
    of docs/json.schema.json's `eval`)."""
    text = stdout.strip()
    start = text.find("{")
    data = json.loads(text[start:] if start >= 0 else text)
    if not isinstance(data.get("hausdorff_percent"), (int, float)):
        raise ValueError("no hausdorff_percent in the JSON of vmas eval (keys: "
                         + ", ".join(sorted(data)) + ")")
    out = {"json": data, "eps_percent": data["hausdorff_percent"]}
    for key in ("surface_to_medial_max_percent", "surface_to_medial_mean_percent",
                "medial_to_surface_max_percent", "medial_to_surface_mean_percent",
                "openings", "reach_percent"):
        if isinstance(data.get(key), (int, float)):
            out[key] = data[key]
    return out


def read_output(entry, result, parse, what):
    """Adds to `entry` what `parse` reads from the standard output of a run (see run()), or the
    run's or the parser's error; returns whether it read."""
    if not result["ok"]:
        entry["error"] = result["error"]
        return False
    try:
        entry.update(parse(result["stdout"]))
    except (ValueError, IndexError) as e:  # json.JSONDecodeError is a ValueError
        entry["error"] = f"cannot read {what}: {e}"
        return False
    return True


def evaluate(binary, shape, medial, timeout, errors_path=None, medial_errors_path=None):
    command = [binary, "eval", shape, medial, "--json"]
    if errors_path:
        command += ["--errors", errors_path]
    if medial_errors_path:
        command += ["--medial-errors", medial_errors_path]
    result = run(command, timeout)
    entry = {"command": " ".join(map(shlex.quote, command)), "seconds": result["seconds"]}
    if result["stderr"]:
        entry["stderr"] = result["stderr"]
    read_output(entry, result, parse_eval, "eval output")
    return entry


def read_mesh(path):
    """Points (n, 3) and triangles (f, 3) of a mesh file as vmas reads it (every point as
    stored)."""
    surface = vmas.read(path)
    return surface.points, surface.faces


def skeletonize(args, shape, out_ply, spheres, memory=False, extra=(), binary=None):
    """Runs `vmas skeletonize --json` (with the options `extra`; `binary`: another vmas than
    --vmas), reads its summary and checks the medial mesh it wrote; memory: also the peak RSS of
    the run (peak_rss_kb, see run())."""
    command = [binary or args.vmas, "skeletonize", shape, "-o", out_ply, "--spheres", str(spheres),
               *extra, "--json"]
    if args.threads:
        command += ["--threads", str(args.threads)]
    result = run(command, args.timeout, memory)
    entry = {"command": " ".join(map(shlex.quote, command)), "wall_s": result["seconds"],
             "stdout": result["stdout"], "stderr": result["stderr"]}
    if memory:
        entry["peak_rss_kb"] = result["peak_rss_kb"]
    if not read_output(entry, result, parse_skeletonize_json,
                       "the JSON summary of vmas skeletonize"):
        return entry
    try:
        medial = vmas.read_medial(out_ply)  # refuses indices out of range and non-finite values
    except (OSError, ValueError) as e:  # vmas.IoError is an OSError
        entry["checks"] = [f"unreadable PLY: {e}"]
        return entry
    # The checks of our output: exactly M spheres, radii positive and finite, no edge or face
    # repeating an index, one connected component (vmas' count, from the JSON).
    radii, checks = medial.radii, []
    if len(radii) != spheres:
        checks.append(f"{len(radii)} spheres (expected {spheres})")
    if bad := int(np.count_nonzero(~np.isfinite(radii) | (radii <= 0))):
        checks.append(f"{bad} radii not positive and finite")
    for name, ids in (("edge", medial.edges), ("face", medial.faces)):
        if repeated := int(np.count_nonzero(np.any(np.diff(np.sort(ids, axis=1)) == 0, axis=1))):
            checks.append(f"{repeated} {name}s with a repeated index")
    if entry["components"] is None:
        checks.append("no component count in the JSON summary")
    elif entry["components"] != 1:
        checks.append(f"{entry['components']} components")
    entry["checks"] = checks
    entry["ply"] = {"spheres": len(radii), "edges": len(medial.edges), "faces": len(medial.faces)}
    return entry
