#!/usr/bin/env python3
"""The installed `nephele` Python module against `nephele render` (issue #16 item 3).

usage: python_module_check.py NEPHELE NEPHELE_GEN SITE_PACKAGES WORKDIR
(run by python_module_test.sh with PYTHONPATH=SITE_PACKAGES, the temporary install's).

The generated storm (wrfout, Lambert, 2 timesteps) and its .nph cache are rendered by the CLI and
by the module from the same scene keys. Tolerance: none. The module renders through the same
engine functions as the CLI (scene/scene_file, engine/scene_render) on the same GL backend, and a
re-render by the CLI is byte-identical (cli.quicklook), so every 8-bit code must be equal; any
difference is a bug in the module (a scene key lost, a dataset read differently). Checked:
  * .nph: scene file, scene dict, data.path from the scene, and the PNG the module writes;
    EGL, and OSMesa in a child process (OSMesa fails after EGL in one process, docs/interop.md);
  * xarray: the wrfout opened with xarray, handed over as a Dataset, against the wrfout scene;
  * numpy: the .nph's extinction of timestep 1 as arrays and as an xarray Dataset of extinction
    against the .nph at timestep 1 (`timestep=`);
  * bare numpy hydrometeor arrays (from_arrays): the wrfout's model fields as the loader reads
    them (Dataset.model_fields) give exactly the file's extinction and frame; the same fields
    computed from the raw wrfout variables with xarray (P+PB, θ and Exner, destaggered (PH+PHB)/g)
    agree within float32 rounding of the Exner power; bad arrays are refused naming the argument;
  * quick look: with no scene, the module frames the data as `nephele render FILE` does: the
    scene equals `--print-scene`'s for the .nph, the wrfout and the arrays (no data.path), and the
    frame of a Renderer without a scene equals the CLI's quick look (160 x 90, broadcast);
  * float32: scene-linear times 2^exposure_ev, the frame opaque: exposure +1 EV doubles RGB exactly;
  * Renderer: a sequence of frames through one persistent renderer (camera, sun, timestep by index
    and by time, the wrfout converted once) equals separate nephele.render calls code for code,
    and the session's counters show what each frame rebuilt: a camera-only frame decodes,
    uploads and lights nothing (counted, not timed);
  * dataset facts: timesteps, times, grid against the .nph header and the wrfout's XLAT/XLONG;
  * errors: Python exceptions of the documented types naming the file and the variable.
"""
import json
import sys
from pathlib import Path

import numpy as np
import xarray as xr
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from script_checks import check, finish, run  # noqa: E402

nephele_cli, gen, site, work = sys.argv[1:5]
work = Path(work)

import nephele  # noqa: E402  (after the arguments: PYTHONPATH names the install under test)


def png(path):
    return np.asarray(Image.open(path).convert("RGBA"))


def same_codes(a, b, what):
    check(a.shape == b.shape, f"{what}: shape {a.shape} vs {b.shape}")
    if a.shape == b.shape:
        d = np.abs(a.astype(int) - b.astype(int))
        print(f"{what}: max |difference| {d.max()} codes, {int((d > 0).sum())} of {d.size} values differ")
        check(d.max() == 0, f"{what}: max |difference| {d.max()} codes")


check(Path(nephele.__file__).resolve().is_relative_to(Path(site).resolve()),
      f"imported {nephele.__file__}, not the installed module under {site}")

# ---- data and the CLI's renders ---------------------------------------------------------------
nc, nph = work / "storm.nc", work / "storm.nph"
run(gen, "wrf", "--proj", "lambert", "--times", "2", "-o", nc)
run(nephele_cli, "convert", nc, "-o", nph, "--no-progress")
keys = {"camera": {"preset": "oblique"}, "sun": {"azimuth_deg": 200, "elevation_deg": 35}, "quality": "draft",
        "output": {"width": 320, "height": 180}, "height_exaggeration": 8}
for name, data in (("nph", nph), ("nc", nc)):
    (work / f"scene_{name}.json").write_text(json.dumps(dict(keys, data={"path": str(data)})))
    run(nephele_cli, "render", work / f"scene_{name}.json", "-o", work / f"cli_{name}.png")
    run(nephele_cli, "render", work / f"scene_{name}.json", "--timestep", "1", "-o", work / f"cli_{name}_t1.png")
cli_nph, cli_nph_t1, cli_nc = png(work / "cli_nph.png"), png(work / "cli_nph_t1.png"), png(work / "cli_nc.png")

# ---- .nph ------------------------------------------------------------------------------------
ds = nephele.open(nph)
check(ds.timestep_count == 2, f".nph: {ds.timestep_count} timesteps, expected 2")
check(ds.times == ["2026-09-01T12:00:00Z", "2026-09-01T13:00:00Z"], f".nph times {ds.times}")
same_codes(nephele.render(ds, work / "scene_nph.json", dtype="uint8", outputs=[work / "py_nph.png"]), cli_nph,
           ".nph, scene file")
same_codes(png(work / "py_nph.png"), cli_nph, ".nph, the PNG the module wrote")
same_codes(nephele.render(ds, keys, dtype="uint8"), cli_nph, ".nph, scene dict")
same_codes(nephele.render(None, work / "scene_nph.json", dtype="uint8", timestep=1), cli_nph_t1,
           "data.path of the scene, timestep=1")

# OSMesa, in a process of its own (first used after EGL, Mesa's OSMesa misses GL 4.5 entry points)
run(nephele_cli, "render", work / "scene_nph.json", "--gl", "osmesa", "-o", work / "cli_osmesa.png")
run(sys.executable, "-c", f"import nephele; nephele.render(nephele.open({str(nph)!r}), {str(work / 'scene_nph.json')!r}, "
    f"gl='osmesa', outputs=[{str(work / 'py_osmesa.png')!r}])")
same_codes(png(work / "py_osmesa.png"), png(work / "cli_osmesa.png"), "OSMesa, scene file")

# float32: what the .exr stores, scene-linear times 2^exposure_ev; the frame is opaque
lin0 = nephele.render(ds, dict(keys, output=dict(keys["output"], exposure_ev=0.0)))
lin1 = nephele.render(ds, dict(keys, output=dict(keys["output"], exposure_ev=1.0)))
check(lin0.dtype == np.float32 and lin0.shape == (180, 320, 4), f"float32 frame: {lin0.dtype} {lin0.shape}")
check(np.isfinite(lin0).all() and (lin0[..., 3] == 1.0).all(), "float32 frame: not finite or not opaque")
check(np.array_equal(lin1[..., :3], 2.0 * lin0[..., :3]), "float32: exposure +1 EV does not double RGB exactly")
check(float(lin0[..., :3].max()) > 0.0, "float32 frame is black")
cloud = nephele.render(ds, keys, cloud_layer=True)
check((cloud[..., 3] >= 0).all() and (cloud[..., 3] <= 1).all() and 0 < cloud[..., 3].mean() < 1,
      f"cloud layer alpha outside [0, 1] or empty/full (mean {cloud[..., 3].mean()})")

# ---- Renderer: one GL context and session for a sequence of frames ----------------------------------
top, low_sun = {"preset": "top"}, {"azimuth_deg": 90, "elevation_deg": 20}
with nephele.Renderer(ds, keys, gl="egl") as r:
    counts = []  # (timestep_decodes, volume_uploads, dlm_builds) after each frame
    frames = []
    for call in (dict(), dict(camera=top), dict(sun=low_sun), dict(time=1), dict(time="2026-09-01T12:00:00Z"),
                 dict(camera=keys["camera"], outputs=[work / "py_renderer.png"])):
        frames.append(r.render(dtype="uint8", **call))
        st = r.stats()
        counts.append((st["timestep_decodes"], st["volume_uploads"], st["dlm_builds"]))
    print(f"Renderer counters (decodes, uploads, DLM builds) after each frame: {counts}")
    expect_counts = [(1, 1, 1), (1, 1, 1), (1, 1, 2), (2, 2, 3), (2, 3, 4), (2, 3, 4)]
    check(counts == expect_counts, f"Renderer counters {counts}, expected {expect_counts}: a camera-only frame must "
          "not decode, upload or light again; a sun change rebuilds only the DLM; a timestep change all (t0 cached)")
    check(not r.stats()["dlm_rebuilt"] and not r.stats()["volume_changed"], f"last frame stats {r.stats()}")
check(r.closed, "Renderer not closed at the end of its with block")
separate = [nephele.render(ds, keys, dtype="uint8"), nephele.render(ds, dict(keys, camera=top), dtype="uint8"),
            nephele.render(ds, dict(keys, camera=top, sun=low_sun), dtype="uint8"),
            nephele.render(ds, dict(keys, camera=top, sun=low_sun), timestep=1, dtype="uint8"),
            nephele.render(ds, dict(keys, camera=top, sun=low_sun), timestep=0, dtype="uint8"),
            nephele.render(ds, dict(keys, sun=low_sun), dtype="uint8")]
for n, (a, b) in enumerate(zip(frames, separate)):
    same_codes(a, b, f"Renderer frame {n} vs nephele.render")
same_codes(png(work / "py_renderer.png"), separate[-1], "Renderer: the PNG of outputs=")
same_codes(frames[0], cli_nph, "Renderer frame 0 vs nephele render")
# a model file: converted once for any number of camera moves (the counters), frames as the CLI's
with nephele.Renderer(nephele.open(nc), keys, gl="egl") as r:
    same_codes(r.render(dtype="uint8"), cli_nc, "Renderer of the wrfout vs nephele render")
    r.render(camera=top)
    r.render(camera={"preset": "overview"}, sun=low_sun)
    check(r.stats()["timestep_decodes"] == 1 and r.stats()["volume_uploads"] == 1,
          f"Renderer of the wrfout converted again: {r.stats()}")

# grid: the header's figures and the footprint against the wrfout's corner mass points
grid = ds.grid(1)
x = xr.open_dataset(nc)
check((grid["nx"], grid["ny"], grid["dx"], grid["dy"]) == (x.sizes["west_east"], x.sizes["south_north"],
                                                           x.attrs["DX"], x.attrs["DY"]),
      f"grid {grid['nx']}x{grid['ny']} at {grid['dx']}x{grid['dy']} m, wrfout {dict(x.sizes)} {x.attrs['DX']}")
check("+proj=lcc" in grid["proj"] and grid["time_utc"] == "2026-09-01T13:00:00Z", f"grid proj/time {grid}")
lat, lon = x["XLAT"].values[0], x["XLONG"].values[0]
corner_points = [(lon[0, 0], lat[0, 0]), (lon[0, -1], lat[0, -1]), (lon[-1, -1], lat[-1, -1]), (lon[-1, 0], lat[-1, 0])]
# outer corners lie half a cell (7.5 km ~ 0.07 deg) outside the corner mass points: within one cell
cell_deg = grid["dx"] / 111e3
for (glon, glat), (mlon, mlat) in zip(grid["lonlat_corners"], corner_points):
    check(abs(glon - mlon) < cell_deg and abs(glat - mlat) < cell_deg,
          f"footprint corner ({glon:.3f}, {glat:.3f}) more than a cell from the mass point ({mlon:.3f}, {mlat:.3f})")

# ---- xarray Dataset of hydrometeors: the wrfout through the WRF loader --------------------------
xd = nephele.from_xarray(x)
check(xd.timestep_count == 2 and xd.times == ds.times, f"xarray: {xd.timestep_count} timesteps {xd.times}")
check(xd.path == f"xarray.Dataset from {nc}", f"xarray dataset named {xd.path!r}")
same_codes(nephele.render(xd, keys, dtype="uint8"), cli_nc, "xarray Dataset of the wrfout vs the wrfout scene")
# against the .nph: the cache's 16-bit quantisation only (docs/conversion.md), figures for the record
d = np.abs(nephele.render(xd, keys, dtype="uint8").astype(int) - cli_nph.astype(int))
print(f"xarray Dataset vs the .nph (16-bit quantised): max {d.max()} codes, mean {d.mean():.4f}")

# ---- numpy arrays and an xarray Dataset of extinction ---------------------------------------------
vol = ds.extinction(1)
check(vol["ice_per_m"].shape == (grid["nz"], grid["ny"], grid["nx"]), f"extinction shape {vol['ice_per_m'].shape}")
check(float(vol["water_per_m"].max()) == grid["max_water_per_m"], "extinction max differs from the grid's")
place = dict(dx=grid["dx"], dy=grid["dy"], dz_m=grid["dz_m"], z_bottom_m=grid["z_bottom_m"], proj=grid["proj"],
             x0=grid["x0"], y0=grid["y0"])
arrays = nephele.from_extinction(**vol, **place, times_utc=[grid["time_utc"]])
same_codes(nephele.render(arrays, keys, dtype="uint8"), cli_nph_t1, "numpy extinction vs the .nph at timestep 1")
z = grid["z_bottom_m"] + (np.arange(grid["nz"]) + 0.5) * grid["dz_m"]
ext = xr.Dataset({"ice_extinction": (("z", "y", "x"), vol["ice_per_m"]),
                  "water_extinction": (("z", "y", "x"), vol["water_per_m"]),
                  "terrain_height_m": (("y", "x"), vol["terrain_height_m"])},
                 coords={"z": z, "y": grid["y0"] + grid["dy"] * np.arange(grid["ny"]),
                         "x": grid["x0"] + grid["dx"] * np.arange(grid["nx"])}, attrs={"proj": grid["proj"]})
same_codes(nephele.render(nephele.from_xarray(ext), keys, dtype="uint8"), cli_nph_t1,
           "xarray Dataset of extinction vs the .nph at timestep 1")


# ---- bare numpy hydrometeor arrays: the loaders' conversion without a file -------------------------
wrf = nephele.open(nc)
fields = [wrf.model_fields(t) for t in range(2)]
volume_keys = [k for k, v in fields[0].items() if isinstance(v, np.ndarray) and v.ndim == 3]
grid_keys = ("terrain_height_m", "proj", "dx", "dy", "x0", "y0", "geographic", "lon", "lat", "model",
             "microphysics_scheme")
check({"qcloud", "qice", "qvapor", "pressure_pa", "temperature_k", "heights_m"} <= set(volume_keys),
      f"model_fields of the wrfout: {volume_keys}")
arrays_ds = nephele.from_arrays(**{k: np.stack([f[k] for f in fields]) for k in volume_keys},
                                **{k: fields[0][k] for k in grid_keys}, times_utc=ds.times, name="wrfout arrays")
check(arrays_ds.times == ds.times and arrays_ds.path == "wrfout arrays", f"from_arrays: {arrays_ds}, {arrays_ds.times}")
for t in range(2):
    a, f = arrays_ds.extinction(t), wrf.extinction(t)
    for k in ("ice_per_m", "water_per_m", "terrain_height_m"):
        check(np.array_equal(a[k], f[k]), f"from_arrays timestep {t}: {k} differs from the wrfout's "
              f"(max {np.abs(a[k] - f[k]).max() if a[k].shape == f[k].shape else 'shape'})")
    ga, gf = arrays_ds.grid(t), wrf.grid(t)
    check(ga == gf, f"from_arrays timestep {t}: grid {ga} vs the wrfout's {gf}")
print("from_arrays of the wrfout's model fields: extinction equal to the file's at both timesteps")
same_codes(nephele.render(arrays_ds, keys, dtype="uint8"), cli_nc, "from_arrays vs nephele render of the wrfout")
# The same fields computed from the raw variables, as a user holding only xarray would (WRF ARW tech
# note §2.1, the loader's constants): only the Exner power's float32 rounding differs (numpy's powf
# against libm's), ~1 ulp of T, so β differs by ~1e-7 relative; tolerance 1e-6 of the largest β.
x0 = x.isel(Time=0)
p_pa = (x0.P + x0.PB).values.astype(np.float32)
theta = x0["T"].values.astype(np.float32) + np.float32(300.0)
t_k = theta * np.power(p_pa * np.float32(1e-5), np.float32(287.0 / 1004.5))
phi = (x0.PH.values.astype(np.float64) + x0.PHB.values.astype(np.float64)) / 9.81
phi = phi.astype(np.float32).astype(np.float64)
z_m = (0.5 * (phi[:-1] + phi[1:])).astype(np.float32)
raw = nephele.from_arrays(qcloud=np.clip(x0.QCLOUD.values, 0, None), qrain=np.clip(x0.QRAIN.values, 0, None),
                          qice=np.clip(x0.QICE.values, 0, None), qsnow=np.clip(x0.QSNOW.values, 0, None),
                          qgraupel=np.clip(x0.QGRAUP.values, 0, None), qvapor=np.clip(x0.QVAPOR.values, 0, None),
                          **{n.lower(): np.clip(x0[wrf_name].values, 0, None) for n, wrf_name in (
                              ("qncloud", "QNCLOUD"), ("qnrain", "QNRAIN"), ("qnice", "QNICE"), ("qnsnow", "QNSNOW"),
                              ("qngraupel", "QNGRAUPEL"))},
                          pressure_pa=p_pa, temperature_k=t_k, heights_m=z_m, terrain_height_m=x0.HGT.values,
                          **{k: fields[0][k] for k in ("proj", "dx", "dy", "x0", "y0", "lon", "lat")},
                          microphysics_scheme=int(x.attrs["MP_PHYSICS"]), times_utc=ds.times[:1], name="xarray fields")
a, f = raw.extinction(0), wrf.extinction(0)
check(a["ice_per_m"].shape == f["ice_per_m"].shape, f"xarray fields: shape {a['ice_per_m'].shape} vs {f['ice_per_m'].shape}")
for k in ("ice_per_m", "water_per_m"):
    if a[k].shape == f[k].shape:
        d = float(np.abs(a[k] - f[k]).max())
        print(f"from_arrays of xarray-computed fields: {k} max |difference| {d:.3g} /m of max {f[k].max():.3g}")
        check(d <= 1e-6 * float(f[k].max()), f"xarray fields: {k} differs by {d} /m")
d = np.abs(nephele.render(raw, keys, dtype="uint8").astype(int) - cli_nc.astype(int))
print(f"from_arrays of xarray-computed fields vs nephele render: max {d.max()} codes, {(d > 0).sum()} values differ")
check(d.max() <= 1, f"xarray fields: frame differs by {d.max()} codes (expected at most 1: ~1e-7 relative in beta)")

# a regular lat-lon grid from 1-D lon/lat: its footprint's outer corners half a cell outside the centres
one_t = {k: fields[0][k] for k in ("qcloud", "qice", "qvapor", "pressure_pa", "temperature_k", "heights_m")}
ny, nx = one_t["qcloud"].shape[1:]
lon_1d, lat_1d = np.linspace(-80.0, -70.0, nx), np.linspace(20.0, 28.0, ny)
latlon = nephele.from_arrays(**one_t, lon=lon_1d, lat=lat_1d).grid(0)
half_dlon, half_dlat = (lon_1d[1] - lon_1d[0]) / 2, (lat_1d[1] - lat_1d[0]) / 2
check(latlon["geographic"] and "+proj=longlat" in latlon["proj"] and
      np.allclose(latlon["lonlat_corners"][0], (-80.0 - half_dlon, 20.0 - half_dlat), atol=1e-9) and
      np.allclose(latlon["lonlat_corners"][2], (-70.0 + half_dlon, 28.0 + half_dlat), atol=1e-9),
      f"from_arrays with 1-D lon/lat: {latlon['proj']}, corners {latlon['lonlat_corners']}")

# ---- quick look: the CLI's framing when no scene is given --------------------------------------------
for what, data in (("nph", ds), ("wrfout", wrf)):
    printed = json.loads(run(nephele_cli, "render", data.path, "--print-scene", "--width", 160, "--height", 90))
    check(nephele.quick_look(data, width=160, height=90) == printed,
          f"quick_look of the {what} differs from --print-scene: {nephele.quick_look(data, width=160, height=90)} "
          f"vs {printed}")
in_memory = nephele.quick_look(arrays_ds, width=160, height=90)
check(in_memory["data"] == {"timestep": 0} and "wrfout arrays" in in_memory["description"]
      and in_memory["height_exaggeration"] == printed["height_exaggeration"], f"quick_look of arrays: {in_memory}")
run(nephele_cli, "render", nph, "--width", 160, "--height", 90, "-o", work / "cli_quick.png")
with nephele.Renderer(ds, gl="egl", width=160, height=90) as r:
    same_codes(r.render(dtype="uint8"), png(work / "cli_quick.png"), "Renderer without a scene vs the CLI's quick look")

# ---- errors name the file and the variable ---------------------------------------------------------
def expect_error(kind, words, call, what):
    try:
        call()
    except nephele.Error as e:
        check(isinstance(e, kind), f"{what}: {type(e).__name__}, expected {kind.__name__}: {e}")
        missing = [w for w in words if w not in str(e)]
        check(not missing, f"{what}: message {str(e)!r} does not name {missing}")
        print(f"{what}: {type(e).__name__}: {e}")
        return
    check(False, f"{what}: no exception")


expect_error(nephele.InputError, [str(work / "missing.nph")], lambda: nephele.open(work / "missing.nph"),
             "missing file")
expect_error(nephele.InputError, ["QCLOUD", str(nc), "at most 0.1"],
             lambda: nephele.render(nephele.from_xarray(x.assign(QCLOUD=x.QCLOUD * 100)), keys),
             "xarray: QCLOUD x 100")
expect_error(nephele.InputError, ["T", str(nc), "missing"],
             lambda: nephele.from_xarray(x.drop_vars("T")).extinction(0), "xarray: no T")
bad_ice = vol["ice_per_m"].copy()
bad_ice[3, 4, 5] = np.nan
expect_error(nephele.InputError, ["my arrays", "ice_per_m"],
             lambda: nephele.from_extinction(bad_ice, vol["water_per_m"], **place, name="my arrays"),
             "numpy: NaN extinction")
expect_error(nephele.InputError, ["<scene dict>", "camera.fvo_deg"],
             lambda: nephele.render(ds, dict(keys, camera={"fvo_deg": 30})), "scene dict: typo")
expect_error(nephele.InputError, ["scene_bad.json", "output.paths[0]"],
             lambda: (work / "scene_bad.json").write_text('{"output": {"paths": ["frame.jpg"]}}') and
             nephele.render(ds, work / "scene_bad.json"), "scene file: bad output")
expect_error(nephele.UsageError, ["--gl vulkan"], lambda: nephele.render(ds, keys, gl="vulkan"), "unknown gl")
expect_error(nephele.InputError, ["<Renderer.render camera/sun>", "camera.fvo_deg"],
             lambda: nephele.Renderer(ds, keys).render(camera={"fvo_deg": 30}), "Renderer: camera typo")
expect_error(nephele.InputError, [str(nph), "2030-01-01"],
             lambda: nephele.Renderer(ds, keys).render(time="2030-01-01T00:00:00Z"), "Renderer: a time not in the data")
closed = nephele.Renderer(ds, keys)
closed.close()
expect_error(nephele.UsageError, ["after close"], lambda: closed.render(), "Renderer: render after close")
one = {k: fields[0][k] for k in volume_keys}
place_arrays = {k: fields[0][k] for k in ("proj", "dx", "dy", "x0", "y0")}
negative = one["qcloud"].copy()
negative[2, 3, 4] = -1e-5
for what, kind, words, kwargs in (
        ("NaN", nephele.InputError, ["my fields", "temperature_k", "NaN"],
         dict(temperature_k=np.where(one["temperature_k"] > 250, np.nan, one["temperature_k"]))),
        ("negative", nephele.InputError, ["my fields", "qcloud", "-1e-05", ">= 0"], dict(qcloud=negative)),
        ("shape", nephele.InputError, ["my fields", "qice", "shape"], dict(qice=one["qice"][:, :-1])),
        ("dtype", nephele.InputError, ["my fields", "pressure_pa", "int64", "floating"],
         dict(pressure_pa=one["pressure_pa"].astype(np.int64))),
        ("Pa as hPa", nephele.InputError, ["my fields", "pressure_pa", "a pressure [Pa]"],
         dict(pressure_pa=one["pressure_pa"] * 100)),
        ("no grid", nephele.UsageError, ["my fields", "dx"], dict(proj="", dx=None))):
    expect_error(kind, words, lambda kw=kwargs: nephele.from_arrays(**{**one, **place_arrays, **kw}, name="my fields"),
                 f"from_arrays: {what}")
expect_error(nephele.InputError, ["my fields", "hydrometeor"], lambda: nephele.from_arrays(
    **{k: v for k, v in one.items() if not k.startswith("q")}, **place_arrays, name="my fields"), "from_arrays: no q")
expect_error(nephele.InputError, ["lon", "increasing"],
             lambda: nephele.from_arrays(**one_t, lon=lon_1d[::-1], lat=lat_1d), "from_arrays: lon decreasing")
check(issubclass(nephele.InputError, ValueError) and issubclass(nephele.IoError, OSError),
      "InputError is not a ValueError or IoError not an OSError")

finish()
print("all checks passed")
