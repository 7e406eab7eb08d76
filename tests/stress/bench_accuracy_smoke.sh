#!/usr/bin/env bash
# Smoke test of `nephele-bench accuracy --quick`: runs it, then checks that accuracy.csv has the
# documented columns, one row per scene × variant, and only finite numbers.
set -euo pipefail
nephele="$1"
out="$2"
rm -rf "$out"
"$nephele" accuracy --quick -o "$out"
csv="$out/accuracy.csv"
test -s "$csv" || { echo "no $csv"; exit 1; }
expected="scene,knob,value,dlm_ms,raycast_ms,total_ms,dlm_mean_nodes,dlm_unbounded_texels,truth_rmse,truth_rel_mse,truth_mean_abs,truth_max_abs,truth_share_off_2_255,truth_alpha_max_abs,truth_noise_rmse,truth_bias_rmse,truth_truncated_share,coverage,ref_rmse,ref_rel_mse,ref_mean_abs,ref_max_abs,ref_share_off_2_255,ref_alpha_max_abs,truth_luminance_bias,truth_rel_mse_noise"
header=$(head -1 "$csv")
[ "$header" = "$expected" ] || { echo "unexpected header: $header"; exit 1; }
python3 - "$csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
scenes = {r["scene"] for r in rows}
assert len(scenes) == 9, f"expected 9 scenes, got {sorted(scenes)}"
assert len(rows) >= 9 * 10, f"only {len(rows)} rows"
for r in rows:
    for k, v in r.items():
        if k in ("scene", "knob", "value"):
            continue
        x = float(v)
        assert math.isfinite(x), f"{r['scene']} {r['knob']}={r['value']}: {k} = {v}"
        if k == "truth_luminance_bias":  # sum Y / sum Y_truth - 1: signed, > -1
            assert x > -1.0, f"{r['scene']} {r['knob']}={r['value']}: {k} = {v}"
            continue
        assert x >= 0.0, f"{r['scene']} {r['knob']}={r['value']}: {k} = {v} < 0"
    assert float(r["total_ms"]) > 0.0
    assert float(r["truth_share_off_2_255"]) <= 1.0 and float(r["ref_share_off_2_255"]) <= 1.0
# The GPU's reference preset renders the same world as its converged CPU twin (no atmosphere, the
# analytic sky all round, as the path tracer): RMSE <= 4e-4 on every quick scene (twenty-eighth
# session). The GPU's default atmosphere left on made it 1e-2, whatever the knobs.
for r in rows:
    if r["knob"] == "preset" and r["value"] == "reference":
        assert float(r["ref_rmse"]) <= 2e-3, f"{r['scene']}: reference preset vs CPU reference RMSE {r['ref_rmse']}"
print(f"accuracy.csv: {len(rows)} rows, {len(scenes)} scenes, all finite")
PY
test -s "$out/accuracy-summary.csv"
