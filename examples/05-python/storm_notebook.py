# %% [markdown]
# # nephele from Python: a wrfout through xarray, numpy arrays in and out
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
# ## 4. Scene-linear floats and files
# `dtype="float32"` gives what an .exr stores (linear light times 2^exposure_ev) for your own
# compositing; `outputs=` writes files as `nephele render -o` does (.png, .exr), with the
# scene's passes when it asks for them (docs/passes.md). One frame per timestep:
for t in range(storm.timestep_count):
    linear = nephele.render(storm, scene, timestep=t, outputs=[out / f"storm_{t:04d}.exr"])
    print(f"timestep {t} ({storm.times[t]}): mean linear radiance {linear[..., :3].mean():.3f}")

# %% [markdown]
# ## 5. Errors name the file and the variable
try:
    nephele.from_xarray(wrf.drop_vars("T")).extinction(0)
except nephele.InputError as e:  # also a ValueError
    print("as expected:", e)
