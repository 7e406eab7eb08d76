#!/usr/bin/env python3
"""OpenVDB round trip of `nephele export-vdb` (issue #16), read back with Debian's python3-openvdb.

usage: vdb_roundtrip.py NEPHELE NEPHELE_GEN NPH_DUMP WORKDIR

The generated storm (wrfout, Lambert) is converted to a .nph cache and exported twice: from the
.nph and straight from the wrfout (unquantised floats). nph_dump decodes the .nph with NphReader,
independently of the exporter. Checked, per timestep:
  * grids ice_extinction, water_extinction, density (fog volumes, 1/m);
  * from the .nph: every voxel equals the decoded cache value exactly, density = ice + water;
  * from the wrfout: every voxel is within the .nph quantisation bound of the cached value,
    |β_vdb − β_nph| ≤ max_t / 131070 (half a 16-bit code step, nph_cache.h, quantize.h), plus
    max_t·2⁻²³ for the float32 rounding of the two values (measured: the error reaches the
    bound itself to 5e-4 of it, so the half step is the real size of the error);
  * sparse: the active voxels are exactly the voxels with β > 0, and the leaf count is exactly the
    number of 8³ blocks holding any of them (no tile of clear air is stored);
  * transform: voxel size (dx, dy, dz) in metres, voxel (0,0,0) at (x0, y0, z_bottom + dz/2) in
    the Lambert projection's metres; the active bounding box is the one of the nonzero voxels;
  * georeference: the frame's PROJ string is the grid's, and the lon/lat corners in the metadata
    lie within one grid cell of the wrfout's XLAT/XLONG corner mass points (read with ncdump).
A geographic grid (ICON regular lat-lon) checks the equirectangular metres of a degree grid.
"""
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyopenvdb as vdb

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from script_checks import check, finish, run  # noqa: E402

nephele, gen, nph_dump, work = sys.argv[1:5]
work = Path(work)
work.mkdir(parents=True, exist_ok=True)


def read_vdb(path):
    grids, file_meta = vdb.readAll(str(path))
    return {g.name: g for g in grids}, file_meta


def dense(grid, shape_xyz):
    a = np.zeros(shape_xyz, dtype=np.float32)
    grid.copyToArray(a, ijk=(0, 0, 0))
    return a  # a[i, j, k]


def dump(nph, t):
    prefix = work / f"dump_{t}"
    run(nph_dump, nph, t, prefix)
    meta = json.loads(Path(f"{prefix}.json").read_text())
    shape_zyx = (meta["nz"], meta["ny"], meta["nx"])
    ice = np.fromfile(f"{prefix}_ice.f32", dtype="<f4").reshape(shape_zyx).transpose(2, 1, 0)
    water = np.fromfile(f"{prefix}_water.f32", dtype="<f4").reshape(shape_zyx).transpose(2, 1, 0)
    return meta, ice, water


def ncdump_corners(nc, var):
    """Values of var[0, j, i] at the four corner mass points (SW, SE, NE, NW), via ncdump."""
    text = run("ncdump", "-v", var, nc)
    ny = int(re.search(r"south_north = (\d+)", text).group(1))
    nx = int(re.search(r"west_east = (\d+)", text).group(1))
    body = text.split(f" {var} =", 2)[-1].split(";")[0]
    values = [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", body)]
    at = lambda j, i: values[j * nx + i]
    return [at(0, 0), at(0, nx - 1), at(ny - 1, nx - 1), at(ny - 1, 0)], nx, ny


# ---- the Lambert storm -----------------------------------------------------------------------
nc = work / "storm.nc"
nph = work / "storm.nph"
run(gen, "wrf", "--proj", "lambert", "--times", "2", "-o", nc)
run(nephele, "convert", nc, "-o", nph, "--no-progress")
run(nephele, "export-vdb", nph, "-o", work / "from_nph" / "storm")
run(nephele, "export-vdb", nc, "-o", work / "from_nc" / "storm")

for t in range(2):
    meta, ice, water = dump(nph, t)
    shape = ice.shape
    grids, file_meta = read_vdb(work / "from_nph" / f"storm_{t:04d}.vdb")
    check(set(grids) == {"ice_extinction", "water_extinction", "density"},
          f"t={t}: grids {sorted(grids)}")
    for name, g in grids.items():
        check(g.gridClass == vdb.GridClass.FOG_VOLUME, f"t={t} {name}: class {g.gridClass}")
        check(g.metadata.get("nephele_units") == "1/m", f"t={t} {name}: units")
        check(g.metadata.get("nephele_time_utc") == meta["time_utc"], f"t={t} {name}: time")
    v_ice = dense(grids["ice_extinction"], shape)
    v_water = dense(grids["water_extinction"], shape)
    v_density = dense(grids["density"], shape)
    check(np.array_equal(v_ice, ice), f"t={t}: ice from .nph differs, max |d| {np.abs(v_ice - ice).max()}")
    check(np.array_equal(v_water, water), f"t={t}: water from .nph differs")
    check(np.array_equal(v_density, ice + water), f"t={t}: density != ice + water")

    # sparse: exactly the nonzero voxels, exactly the 8^3 blocks holding them
    nonzero = (ice + water) > 0
    g = grids["density"]
    check(g.activeVoxelCount() == int(nonzero.sum()),
          f"t={t}: {g.activeVoxelCount()} active voxels, {int(nonzero.sum())} nonzero")
    blocks = {(i // 8, j // 8, k // 8) for i, j, k in zip(*np.nonzero(nonzero))}
    dense_blocks = math.prod(math.ceil(n / 8) for n in shape)
    check(g.leafCount() == len(blocks), f"t={t}: {g.leafCount()} leaves, {len(blocks)} occupied blocks")
    print(f"t={t}: {int(nonzero.sum())} of {nonzero.size} voxels active, {g.leafCount()} of "
          f"{dense_blocks} leaves stored")
    check(g.leafCount() < dense_blocks, f"t={t}: every leaf stored, the grid is not sparse")
    idx = np.argwhere(nonzero)
    lo, hi = g.evalActiveVoxelBoundingBox()
    check(tuple(lo) == tuple(idx.min(0)) and tuple(hi) == tuple(idx.max(0)),
          f"t={t}: active bbox {lo}..{hi}, nonzero voxels span {idx.min(0)}..{idx.max(0)}")

    # transform: metres in the Lambert frame
    size = g.transform.voxelSize()
    origin = g.transform.indexToWorld((0, 0, 0))
    expect_origin = (meta["x0"], meta["y0"], meta["z_bottom_m"] + 0.5 * meta["dz_m"])
    check(np.allclose(size, (meta["dx"], meta["dy"], meta["dz_m"]), rtol=1e-12),
          f"t={t}: voxel size {size}, expected {(meta['dx'], meta['dy'], meta['dz_m'])}")
    check(np.allclose(origin, expect_origin, rtol=0, atol=1e-6),
          f"t={t}: voxel (0,0,0) at {origin}, expected {expect_origin}")
    far = g.transform.indexToWorld(tuple(float(n - 1) for n in shape))
    expect_far = (meta["x0"] + (shape[0] - 1) * meta["dx"], meta["y0"] + (shape[1] - 1) * meta["dy"],
                  meta["z_bottom_m"] + (shape[2] - 0.5) * meta["dz_m"])
    check(np.allclose(far, expect_far, rtol=0, atol=1e-6), f"t={t}: far voxel at {far}, expected {expect_far}")
    check(g.metadata["nephele_frame_proj"] == meta["proj_definition"] and "+proj=lcc" in meta["proj_definition"],
          f"t={t}: frame proj {g.metadata['nephele_frame_proj']!r}")

    # the same timestep exported straight from the wrfout: within the cache's quantisation bound
    grids_nc, _ = read_vdb(work / "from_nc" / f"storm_{t:04d}.vdb")
    for name, cached, scale in (("ice_extinction", ice, meta["max_ice_per_m"]),
                                ("water_extinction", water, meta["max_water_per_m"])):
        raw = dense(grids_nc[name], shape)
        # half a code step, plus the float32 rounding of the decoded and of the exported value
        # (each within half an ulp of values <= max, i.e. max * 2^-24)
        bound = scale * (1.0 / 131070.0 + 2.0 ** -23)
        err = float(np.abs(raw - cached).max())
        print(f"t={t} {name}: max |wrfout - .nph| = {err:.3g} /m, bound {bound:.3g} /m")
        check(err <= bound, f"t={t} {name}: wrfout export differs from the .nph by {err}, bound {bound}")
        lo2, hi2 = grids_nc[name].evalActiveVoxelBoundingBox()
        check(hi2[2] < shape[2], f"t={t} {name}: wrfout export reaches layer {hi2[2]} above the cache's {shape[2]}")

# georeference: corners of the footprint against the wrfout's corner mass points
lat, nx, ny = ncdump_corners(nc, "XLAT")
lon, _, _ = ncdump_corners(nc, "XLONG")
corners = [tuple(map(float, c.split(","))) for c in g.metadata["nephele_lonlat_corners"].split(";")]
cell_deg = meta["dx"] / 111000.0  # one grid spacing in degrees of latitude (upper bound)
for (clon, clat), mlon, mlat, name in zip(corners, lon, lat, ("SW", "SE", "NE", "NW")):
    d_lat = abs(clat - mlat)
    d_lon = abs(clon - mlon) * math.cos(math.radians(mlat))
    check(d_lat < cell_deg and d_lon < cell_deg,
          f"{name} corner {clon:.4f},{clat:.4f} is not within a cell of mass point {mlon:.4f},{mlat:.4f}")

# ---- a geographic grid: degrees become equirectangular metres ---------------------------------
icon = work / "icon.nc"
run(gen, "icon", "-o", icon)
run(nephele, "convert", icon, "-o", work / "icon.nph", "--no-progress")
run(nephele, "export-vdb", work / "icon.nph", "-o", work / "icon" / "icon", "-t", "0")
meta, ice, water = dump(work / "icon.nph", 0)
grids, _ = read_vdb(work / "icon" / "icon_0000.vdb")
g = grids["density"]
R = 6370000.0  # nephele's flat-map sphere (volume/volume_frame.h)
lat_c = meta["y0"] + 0.5 * (meta["ny"] - 1) * meta["dy"]
k = R * math.pi / 180.0
expect_size = (meta["dx"] * k * math.cos(math.radians(lat_c)), meta["dy"] * k, meta["dz_m"])
check(np.allclose(g.transform.voxelSize(), expect_size, rtol=1e-12),
      f"icon: voxel size {g.transform.voxelSize()}, expected {expect_size}")
origin = g.transform.indexToWorld((0, 0, 0))
expect_origin = (meta["x0"] * expect_size[0] / meta["dx"], meta["y0"] * k, meta["z_bottom_m"] + 0.5 * meta["dz_m"])
check(np.allclose(origin, expect_origin, rtol=1e-12), f"icon: origin {origin}, expected {expect_origin}")
frame = g.metadata["nephele_frame_proj"]
check(f"+proj=eqc +lat_ts={lat_c:.10g}" in frame and "+R=6370000" in frame, f"icon: frame proj {frame!r}")
check(np.array_equal(dense(g, ice.shape), ice + water), "icon: density differs from the cache")

# ---- bad requests get clear errors and leave no file ------------------------------------------
def run_rc(*cmd):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    return r.returncode, r.stderr

rc, err = run_rc(nephele, "export-vdb", nph, "-o", work / "bad" / "storm", "-t", "5")
check(rc == 2 and "--timestep 5" in err and str(nph) in err and "2 timesteps" in err,
      f"timestep out of range: rc {rc}, stderr {err!r}")
check(not (work / "bad").exists() or not any((work / "bad").iterdir()), "files left after a bad --timestep")
blocker = work / "not_a_folder"
blocker.write_text("a file where the output folder should be\n")
rc, err = run_rc(nephele, "export-vdb", nph, "-o", blocker / "storm")
check(rc == 1 and "not_a_folder" in err, f"output under a file: rc {rc}, stderr {err!r}")

finish()
print("vdb round trip: all checks passed")
