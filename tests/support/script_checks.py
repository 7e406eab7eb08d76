"""What the Python test scripts share (tests/interop/vdb_roundtrip.py, tests/python/...):
collect failed checks instead of stopping at the first, run a tool and stop on its failure.

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
    from script_checks import check, finish, run
"""
import subprocess
import sys

failures = []


def check(ok, what):
    """Records `what` as a failure (and prints it) unless `ok`."""
    if not ok:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def run(*cmd):
    """Runs a command, returns its stdout; exits the script with its stderr when it fails."""
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} -> rc {r.returncode}\n{r.stderr}")
    return r.stdout


def finish():
    """Exits non-zero when any check failed."""
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
