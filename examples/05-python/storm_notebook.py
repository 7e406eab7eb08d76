# %% [markdown]
# # nephele from Python: a wrfout through xarray, numpy arrays in and out, a persistent renderer
#
# A notebook as a plain script: the `# %%` cells run one by one in Jupyter (jupytext), VS Code or
# Spyder, or all at once with `python3 storm_notebook.py WRFOUT OUT_DIR`. Needs the installed
# module (`make install`, then `PYTHONPATH=<prefix>/lib/python3/dist-packages`; docs/interop.md)
# and Debian's python3-xarray / python3-netcdf4. Example data: `nephele-gen wrf -o wrfout.nc`
# (the generated hurricane; `--size realistic` for the 500 x 500 column one).
import os
import sys
from pathlib import Path

import numpy as np
import xarray as xr
from PIL import Image

import nephele

wrfout = sys.argv[1] if len(sys.argv) > 1 else "wrfout.nc"
out = Path(sys.argv[2] if len(sys.argv) > 2 else "python-example")
out.mkdir(parents=True, exist_ok=True)
# Frame size and quality: smaller and "draft" for a quick try (the test runs it at 320 x 180).
WIDTH, HEIGHT = int(os.environ.get("WIDTH", 960)), int(os.environ.get("HEIGHT", 540))
QUALITY = os.environ.get("QUALITY", "broadcast")
BASEMAP = os.environ.get("BASEMAP", "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg")  # "": none

# %% [markdown]
# ## 1. Model output as xarray opens it
# Any Dataset laid out as a wrfout (QCLOUD, QRAIN, QICE, ... with P, PB, T, PH, PHB, XLAT, XLONG
# and WRF's global attributes) or as ICON output works: nephele hands it to the same loaders as
# `nephele render wrfout.nc`, so the optics (Nes 2008 eq. 5.3) and the checks are the same.
wrf = xr.open_dataset(wrfout)
print(wrf["QCLOUD"].dims, float(wrf["QCLOUD"].max()), "kg/kg")
storm = nephele.from_xarray(wrf)
print(storm, storm.times)
grid = storm.grid(0)  # sizes, spacing, projection, heights and the footprint's lon/lat corners
print(f"{grid['nx']} x {grid['ny']} x {grid['nz']} voxels, dz {grid['dz_m']} m, corners {grid['lonlat_corners']}")

# %% [markdown]
# ## 2. A scene: the keys of a scene file (docs/scene-file.md), as a dict
# Here Blue Marble under the clouds and the sun where it stood at the model's time.
scene = {
    "camera": {"preset": "oblique", "azimuth_deg": 200, "elevation_deg": 30},
    "sun": {"from_time": True, "colour": [1.0, 0.97, 0.92]},
    "basemap": {"path": BASEMAP, "margin": 0.3} if BASEMAP else None,
    "quality": QUALITY,
    "output": {"width": WIDTH, "height": HEIGHT},
    "height_exaggeration": 8,
}
frame = nephele.render(storm, scene, dtype="uint8")  # (height, width, 4) display codes, as the PNG
Image.fromarray(frame).save(out / "storm.png")  # in a notebook: display(Image.fromarray(frame))

# %% [markdown]
# ## 3. Arrays out, arrays in: the extinction, edited with numpy
# `extinction(t)` gives β [1/m] per voxel (z, y, x) for ice (ice, snow, graupel, hail) and liquid
# water (cloud, rain). Keep only the liquid water to see where the ice shield was, and render that
# from the same camera: `from_extinction` takes arrays from anywhere (another model, an LES, a
# retrieval), with the grid's spacing and projection.
volumes = storm.extinction(0)
ice_optical_depth = volumes["ice_per_m"].sum(axis=0) * grid["dz_m"]  # vertical optical depth of ice
print(f"ice: largest vertical optical depth {ice_optical_depth.max():.1f}, "
      f"{(ice_optical_depth > 1).mean():.0%} of the columns above 1")
water_only = nephele.from_extinction(
    np.zeros_like(volumes["ice_per_m"]), volumes["water_per_m"], terrain_height_m=volumes["terrain_height_m"],
    dx=grid["dx"], dy=grid["dy"], dz_m=grid["dz_m"], z_bottom_m=grid["z_bottom_m"], proj=grid["proj"],
    x0=grid["x0"], y0=grid["y0"], times_utc=[grid["time_utc"]], name="liquid water only")
no_ice = nephele.render(water_only, scene, dtype="uint8")

# Side by side for docs/interop.md (left: the model's clouds; right: without the ice).
Image.fromarray(np.concatenate([frame, no_ice], axis=1)).save(out / "storm-and-liquid-only.png")

# %% [markdown]
# ## 4. Hydrometeors as bare numpy arrays
# Fields from anywhere — wrf-python, MetPy, another model — go through the same conversion as a
# wrfout: mixing ratios [kg/kg], full pressure [Pa], air temperature [K] and the mass levels'
# heights [m], (z, y, x) or (time, z, y, x). Computed here from the wrfout's raw variables as WRF
# defines them (ARW tech note §2.1): p = P + PB, T = (θ' + 300 K)(p / 1000 hPa)^(R_d/c_p),
# heights from the geopotential on w levels averaged to mass levels. Then: no rain.
w0 = wrf.isel(Time=0)
p_pa = (w0.P + w0.PB).values
t_k = (w0["T"].values + 300.0) * (p_pa / 1e5) ** (287.0 / 1004.5)
z_w = ((w0.PH + w0.PHB) / 9.81).values
heights_m = 0.5 * (z_w[:-1] + z_w[1:])
q = {name.lower().replace("qgraup", "qgraupel"): np.clip(w0[name].values, 0, None)  # WRF's advection noise
     for name in ("QCLOUD", "QICE", "QSNOW", "QGRAUP", "QVAPOR") if name in w0}
q.update({name.lower(): w0[name].values for name in ("QNCLOUD", "QNICE", "QNSNOW", "QNGRAUPEL") if name in w0})
no_rain = nephele.from_arrays(**q, pressure_pa=p_pa, temperature_k=t_k, heights_m=heights_m,
                              terrain_height_m=w0.HGT.values, proj=grid["proj"], dx=grid["dx"], dy=grid["dy"],
                              x0=grid["x0"], y0=grid["y0"], microphysics_scheme=int(wrf.attrs.get("MP_PHYSICS", -1)),
                              times_utc=storm.times[:1], name="wrfout arrays without rain")
print(no_rain, "largest water extinction", no_rain.grid(0)["max_water_per_m"], "/m")

# %% [markdown]
# ## 5. A renderer kept between frames: scene-linear floats and files
# `nephele.Renderer` keeps its GL context, the volume and the deep light map: a new camera only
# ray casts again, a new sun relights, a new timestep loads (converts) and relights. Each frame is
# what `nephele.render` gives for the same scene. `dtype="float32"` gives what an .exr stores
# (linear light times 2^exposure_ev) for your own compositing; `outputs=` writes files as
# `nephele render -o` does (.png, .exr). One frame per timestep, then the camera around the storm:
with nephele.Renderer(storm, scene) as renderer:
    for t in range(storm.timestep_count):
        linear = renderer.render(time=t, outputs=[out / f"storm_{t:04d}.exr"])
        print(f"timestep {t} ({storm.times[t]}): mean linear radiance {linear[..., :3].mean():.3f}")
    for azimuth in (110, 290):
        renderer.render(camera=dict(scene["camera"], azimuth_deg=azimuth), outputs=[out / f"orbit_{azimuth}.png"])
        print(f"camera at azimuth {azimuth}: rebuilt", {k: v for k, v in renderer.stats().items() if k in (
            "volume_changed", "dlm_rebuilt", "volume_uploads", "dlm_builds", "timestep_decodes")})

# %% [markdown]
# ## 6. No scene at all: the CLI's quick look
# Without a scene, render() and Renderer frame the data as `nephele render wrfout.nc` does; the
# scene is a dict to inspect, edit and pass on (here printed, at this notebook's frame size).
look = nephele.quick_look(storm, width=WIDTH, height=HEIGHT)
print("quick look:", look["camera"], look["sun"], "height exaggeration", look["height_exaggeration"])

# %% [markdown]
# ## 7. Errors name the file and the variable
try:
    nephele.from_xarray(wrf.drop_vars("T")).extinction(0)
except nephele.InputError as e:  # also a ValueError
    print("as expected:", e)
try:
    nephele.from_arrays(**dict(q, qice=-q["qice"]), pressure_pa=p_pa, temperature_k=t_k, heights_m=heights_m,
                        proj=grid["proj"], dx=grid["dx"], dy=grid["dy"])
except nephele.InputError as e:
    print("as expected:", e)
