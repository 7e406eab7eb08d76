#!/usr/bin/env bash
# Smoke test of `nephele-bench accuracy --compare-ms --quick` (issue 12): runs it, then checks that
# ms-comparison.md has the two_stream row and the coarse diffusion volume's rows
# (lighting/diffusion_volume.h) and the Monte Carlo radiance volume's (reference/mc_radiance_volume.h)
# for all nine scenes, with finite numbers only.
set -euo pipefail
nephele="$1"
out="$2"
rm -rf "$out"
"$nephele" accuracy --compare-ms --quick -o "$out"
md="$out/ms-comparison.md"
test -s "$md" || { echo "no $md"; exit 1; }
python3 - "$md" <<'PY'
import math, re, sys
rows = [l for l in open(sys.argv[1]) if l.startswith("| ")]
def row(name):
    hits = [l for l in rows if l.startswith("| " + name)]
    assert hits, f"no row {name!r}"
    return hits[0]
for name in ("**two_stream**", "diffusion volume 3-D (DLM source, physical drift)",
             "diffusion volume, the grid's columns (column beam, two_stream drift)",
             "two_stream x 3-D/1-D ratio (column beam, physical drift)",
             "MC radiance volume (cells 4x4x2, orders >= 1), P8 + exact beam",
             "MC radiance volume (cells 4x4x2, orders >= 2), P8 + DLM single + forwardLobe"):
    cells = [c.strip() for c in row(name).strip().strip("|").split("|")]
    assert len(cells) == 4 + 9, f"{name}: {len(cells) - 4} scenes"
    for c in cells[2:]:
        for x in re.findall(r"[-+]?[0-9.]+(?:e[-+]?[0-9]+)?|nan|inf", c):
            assert math.isfinite(float(x)), f"{name}: {c}"
print(f"ms-comparison.md: {len(rows)} rows, diffusion and Monte Carlo rows finite")
PY
