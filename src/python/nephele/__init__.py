"""nephele: volumetric clouds from weather model output, from Python (issue #16 item 3).

    import nephele
    ds = nephele.open("storm.nph")                  # or a wrfout, ICON NetCDF/GRIB2 file or folder
    rgba = nephele.render(ds, {"camera": {"preset": "oblique"}, "output": {"width": 640, "height": 360}})
    ds = nephele.from_xarray(xarray.open_dataset("wrfout_d01.nc"))   # hydrometeors -> the same loaders
    ds = nephele.from_extinction(ice, water, dx=3000, dy=3000, dz_m=250)  # or extinction itself
    ds = nephele.from_arrays(qcloud=qc, qice=qi, pressure_pa=p, temperature_k=t, heights_m=z, lon=lon, lat=lat)
    with nephele.Renderer(ds, scene) as r:          # keeps its GL context, volume and light map
        frames = [r.render(camera={"preset": "oblique", "azimuth_deg": a}) for a in range(0, 360, 30)]
    rgba = nephele.render(ds)                       # no scene: the CLI's quick look (quick_look(ds))

Everything runs in nephele's engine (the compiled `nephele._nephele`): datasets are opened by the
loaders of `nephele render`, scenes take the keys of its JSON scene files (docs/scene-file.md) and
frames are rendered headless in a GL context of the module's own (EGL, else OSMesa), with the GIL
released. Errors are `nephele.Error` subclasses whose messages name the file, the variable and what
was expected: InputError (bad data or scene; also a ValueError), UsageError (a bad argument; also a
ValueError), IoError (a file that cannot be read or written; also an OSError), GlError.
See docs/interop.md ("Python") and examples/05-python/.
"""
import contextlib
import json
import os
import tempfile

from . import _nephele
from ._nephele import Error, GlError, InputError, IoError, UsageError

__all__ = ["Dataset", "Error", "GlError", "InputError", "IoError", "Renderer", "UsageError", "from_arrays",
           "from_extinction", "from_xarray", "open", "quick_look", "render"]

# Variable names an xarray Dataset of extinction may use (the first of each pair that exists):
# the grids of `nephele export-vdb` and the arrays of ExtinctionVolumes.
_EXTINCTION_NAMES = (("ice_extinction", "ice_per_m"), ("water_extinction", "water_per_m"))


class Dataset:
    """Timesteps of extinction volumes, read (and for model files converted) on demand.

    path, timestep_count, times (ISO 8601 UTC strings, None where the data has no time),
    source_file(t), grid(t) (sizes, spacings, vertical extent, projection, lon/lat corners),
    extinction(t) (numpy arrays: the keywords of from_extinction)."""

    def __init__(self, handle, aliases=None, keep=None):
        self._handle = handle  # nephele._nephele.Dataset (engine::Dataset)
        self._aliases = aliases or {}  # temporary file -> what it stands for, in messages
        self._keep = keep  # e.g. the temporary folder of from_xarray, removed with the dataset

    @property
    def path(self):
        return next(iter(self._aliases.values()), None) or self._handle.path

    @property
    def timestep_count(self):
        return self._handle.timestep_count

    @property
    def times(self):
        return self._handle.times

    def source_file(self, timestep):
        with _named_errors(self._aliases):
            return self._aliases.get(self._handle.source_file(timestep), self._handle.source_file(timestep))

    def grid(self, timestep=0):
        with _named_errors(self._aliases):
            return self._handle.grid(timestep)

    def extinction(self, timestep=0):
        with _named_errors(self._aliases):
            return self._handle.extinction(timestep)

    def model_fields(self, timestep=0):
        """Timestep t's model fields as the WRF/ICON loaders read them, as numpy arrays: the
        keywords of from_arrays (qcloud, ..., pressure_pa, temperature_k, heights_m, the grid), so
        `nephele.from_arrays(**ds.model_fields(t))` converts exactly as the file does. Model files
        only (not a .nph cache or arrays)."""
        path, t = self._handle.path, timestep
        if not os.path.exists(path) and not any(c in path for c in "*?["):  # a series of files: by file
            path, t = self._handle.source_file(timestep), self._time_in_file(timestep)
        with _named_errors(self._aliases):
            f = _nephele.model_fields(path, t)
        time_utc = f.pop("time_utc")
        f["times_utc"] = [time_utc] if time_utc else None
        return f

    def _time_in_file(self, timestep):
        """Index of timestep t in its own file (a series counts across files)."""
        source = self._handle.source_file(timestep)
        return sum(1 for t in range(timestep) if self._handle.source_file(t) == source)

    def __repr__(self):
        return f"<nephele.Dataset {self.path!r}: {self.timestep_count} timesteps>"


# Encodings from_xarray keeps when it writes a Dataset for the loaders (see there).
_KEPT_ENCODINGS = ("dtype", "_FillValue", "missing_value", "scale_factor", "add_offset", "units", "calendar")


def open(path):  # noqa: A001 (the module's verb, as `nephele render FILE`)
    """A dataset from a .nph cache, a wrfout, an ICON NetCDF or GRIB2 file, a folder of GRIB2
    files or a pattern; a list of model files is one time-ordered series (`nephele convert A B`)."""
    if isinstance(path, (list, tuple)):
        return Dataset(_nephele.open_series([os.fspath(p) for p in path]))
    return Dataset(_nephele.open(os.fspath(path)))


def from_extinction(ice_per_m, water_per_m, *, dx, dy, dz_m, z_bottom_m=0.0, proj="", x0=0.0, y0=0.0,
                    geographic=False, times_utc=None, terrain_height_m=None, name="<numpy arrays>"):
    """A dataset of extinction coefficients [1/m] already computed: arrays (z, y, x) for one timestep
    or (time, z, y, x), x fastest as in a .nph cache (volume/extinction_volumes.h).

    dx, dy: grid spacing in the units of `proj` (metres; degrees when `geographic`); dz_m: layer
    thickness, layer k centred at z_bottom_m + (k + 1/2) dz_m above sea level; x0, y0: projected
    coordinates of column (0, 0); proj: PROJ string ("" = Cartesian, no place on Earth);
    times_utc: one ISO 8601 time per timestep (or None); terrain_height_m: (y, x) ground heights.
    The arrays are checked as a cache would hold them (InputError naming `name` and the array)."""
    return Dataset(_nephele.from_extinction(ice_per_m, water_per_m, float(dx), float(dy), float(dz_m), float(z_bottom_m),
                                    proj, float(x0), float(y0), bool(geographic), list(times_utc or []),
                                    terrain_height_m, name))


# from_arrays' hydrometeor keywords: WRF's Q* names in lower case (io::Hydrometeor order)
_MIXING_RATIOS = ("qcloud", "qrain", "qice", "qsnow", "qgraupel", "qhail")
_NUMBERS = ("qncloud", "qnrain", "qnice", "qnsnow", "qngraupel", "qnhail")


def from_arrays(*, pressure_pa, temperature_k, heights_m, qcloud=None, qrain=None, qice=None, qsnow=None,
                qgraupel=None, qhail=None, qncloud=None, qnrain=None, qnice=None, qnsnow=None, qngraupel=None,
                qnhail=None, qvapor=None, cloud_cover=None, terrain_height_m=None, lon=None, lat=None,
                proj="", dx=None, dy=None, x0=0.0, y0=0.0, geographic=False, model="wrf", microphysics_scheme=-1,
                times_utc=None, earth_radius_m=6370000.0, name="<numpy arrays>"):
    """A dataset of hydrometeors on model levels as bare numpy arrays, converted to extinction by
    the functions that convert WRF and ICON files (Nes 2008 eq. 5.3, the same vertical resampling).

    Fields (z, y, x) or (time, z, y, x), level 0 at the bottom, x fastest (C order), float32 or
    float64: qcloud, qrain, qice, qsnow, qgraupel, qhail (at least one) and qvapor [kg/kg]:
    per kg of dry air for model="wrf" (WRF's Q*), per kg of moist air for model="icon" (ICON's
    specific contents q*); qncloud, ..., qnhail: number concentrations [1/kg] of two-moment
    schemes (WRF's QN*: the effective radii follow them); pressure_pa (full pressure, WRF P + PB), temperature_k (air temperature,
    not WRF's perturbation potential temperature), heights_m (mass levels above sea level, WRF's
    destaggered (PH + PHB)/g); cloud_cover (ICON clc / 100, enables its corrections).
    terrain_height_m (y, x): ground above sea level. microphysics_scheme: WRF's MP_PHYSICS.
    Grid: either lon and lat as 1-D increasing, uniformly spaced column centres [deg] (a regular
    lat-lon grid on a sphere of earth_radius_m), or proj (PROJ string, "" for a Cartesian grid)
    with dx, dy, x0, y0 (spacing and centre of column (0, 0) in its units; degrees when
    geographic), optionally with 2-D lon and lat of every column (WRF's XLONG, XLAT).
    times_utc: one ISO 8601 time per timestep. Values are checked as the loaders check a file's
    (finite, in range; negative mixing ratios are refused, not clamped): InputError naming `name`
    and the argument. Dataset.model_fields(t) of a model file gives these keywords."""
    fields = {k: v for k, v in (("pressure_pa", pressure_pa), ("temperature_k", temperature_k),
                                ("heights_m", heights_m), ("qvapor", qvapor), ("cloud_cover", cloud_cover),
                                *((q, a) for q, a in zip(_MIXING_RATIOS, (qcloud, qrain, qice, qsnow, qgraupel, qhail))),
                                *((n, a) for n, a in zip(_NUMBERS, (qncloud, qnrain, qnice, qnsnow, qngraupel, qnhail))))
              if v is not None}
    lon_2d = lat_2d = None
    if lon is not None or lat is not None:
        if lon is None or lat is None:
            raise InputError(f"{name}: {'lat' if lon is None else 'lon'} given without "
                             f"{'lon' if lon is None else 'lat'}, expected both")
        import numpy as np
        lon_a, lat_a = np.asarray(lon, dtype="float64"), np.asarray(lat, dtype="float64")
        if lon_a.ndim == 1 and lat_a.ndim == 1:
            if proj or dx is not None:
                raise UsageError(f"{name}: 1-D lon and lat define a regular lat-lon grid: give them or proj/dx/dy, not both")
            proj, geographic = f"+proj=longlat +R={earth_radius_m:.17g} +no_defs", True
            (x0, dx), (y0, dy) = (_uniform_axis(a, n, name) for a, n in ((lon_a, "lon"), (lat_a, "lat")))
        elif lon_a.ndim == 2 and lat_a.ndim == 2:
            if dx is None or dy is None:
                raise UsageError(f"{name}: 2-D lon and lat are the columns' positions only: give proj, dx, dy, x0 and "
                                 "y0 of the grid's projection too (or 1-D lon and lat of a regular lat-lon grid)")
            lon_2d, lat_2d = lon_a, lat_a
        else:
            raise InputError(f"{name}: lon has {lon_a.ndim} and lat {lat_a.ndim} dimensions, expected both 1-D "
                             "(a regular lat-lon grid) or both 2-D (y, x)")
    if dx is None or dy is None:
        raise UsageError(f"{name}: no grid: give lon and lat (1-D, degrees) or dx and dy (with proj, x0, y0)")
    return Dataset(_nephele.from_arrays(fields, terrain_height_m, proj, float(dx), float(dy), float(x0), float(y0),
                                        bool(geographic), lon_2d, lat_2d, model, int(microphysics_scheme),
                                        list(times_utc or []), name))


def _uniform_axis(a, what, name):
    """(first value, spacing) of a 1-D increasing, uniformly spaced coordinate."""
    if a.size < 2 or not (a[1:] > a[:-1]).all():
        raise InputError(f"{name}: {what} is not increasing (or has fewer than 2 values), expected the column "
                         "centres of a regular grid in increasing order (flip the arrays' axis)")
    step = (a[-1] - a[0]) / (a.size - 1)
    if abs((a[1:] - a[:-1]) - step).max() > 1e-6 * step:
        raise InputError(f"{name}: {what} is not uniformly spaced, expected a regular lat-lon grid")
    return float(a[0]), float(step)


def from_xarray(dataset, *, name=None):
    """A dataset from an xarray.Dataset.

    * Hydrometeors laid out as a model writes them — a wrfout's QCLOUD, QICE, ... with P, PB, T,
      PH, PHB (and HGT, XLAT, XLONG, the global attributes DX, MAP_PROJ, ...), or ICON's qc, qi,
      ... with temp, pres and the heights — go through the very loaders `nephele render` runs on
      files (the Dataset is written to a temporary NetCDF file with xarray's own writer), so the
      checks, the optics and the vertical grid are the same and errors name the variable.
    * Extinction — variables `ice_extinction` and `water_extinction` (or `ice_per_m`,
      `water_per_m`) with dimensions (z, y, x) or (time, z, y, x) and 1-D coordinates of the same
      names as the last three dimensions (x, y: projected column centres, z: layer centres [m]) —
      become a dataset as from_extinction; attribute `proj` (PROJ string) places it on the Earth,
      an optional variable `terrain_height_m` (y, x) gives the ground.

    `name` stands for the dataset in messages (default: the file xarray read it from)."""
    source = dataset.encoding.get("source")
    label = name or (f"xarray.Dataset from {source}" if source else "xarray.Dataset")
    names = [next((n for n in pair if n in dataset.variables), None) for pair in _EXTINCTION_NAMES]
    if all(names):
        return _extinction_from_xarray(dataset, names, label)
    tmp = tempfile.TemporaryDirectory(prefix="nephele-xarray-")  # in $TMPDIR
    path = os.path.join(tmp.name, "dataset.nc")
    # Uncompressed: a Dataset xarray read from a deflated wrfout carries the file's compression in
    # its encodings, and deflating again took twice as long as writing the raw floats (realistic
    # storm: 40 s against 20 s, docs/interop.md). Types, packing, fill values and time units stay.
    plain = dataset.copy(deep=False)
    for var in plain.variables.values():
        var.encoding = {k: v for k, v in var.encoding.items() if k in _KEPT_ENCODINGS}
    plain.to_netcdf(path, format="NETCDF4")
    with _named_errors({path: label}):
        # the file lives as long as the dataset: timesteps are read on demand
        return Dataset(_nephele.open(path), aliases={path: label}, keep=tmp)


def render(dataset=None, scene=None, *, gl="auto", outputs=None, width=None, height=None, timestep=None,
           dtype="float32", cloud_layer=False):
    """Renders one frame headless and returns it as a numpy array (height, width, 4), row 0 at top.

    dataset: from open/from_xarray/from_extinction, or None to open the scene's data.path.
    scene:   a dict with the keys of a scene file (docs/scene-file.md; relative paths against the
             working directory), the path of a scene file (JSON), or None for the CLI's quick look
             at the dataset (quick_look(): `nephele render FILE` without a scene file).
    gl:      "auto" (NEPHELE_GL, else EGL then OSMesa), "egl" or "osmesa".
    outputs: image files (.png/.exr), replacing output.paths as `nephele render -o` does; the
             scene's output.paths and output.pass_files are written either way.
    width, height, timestep: override output.width/height and data.timestep (as the CLI flags).
    dtype:   "float32": scene-linear RGBA times 2^output.exposure_ev, as an .exr output stores it
             (the frame is composited over the ground: alpha 1); "uint8": the display codes of a
             .png output (tone curve + sRGB, or output.display through OpenColorIO), straight alpha.
    cloud_layer: return the premultiplied cloud layer alone instead of the frame (`--layer`).

    Each call is a new GL context and session: for several frames of one dataset use Renderer."""
    aliases = dataset._aliases if dataset is not None else {}
    if scene is None and dataset is not None:
        scene = quick_look(dataset, width=width or 1920, height=height or 1080)
    with _named_errors(aliases):
        return _nephele.render(None if dataset is None else dataset._handle, *_scene_args(scene), os.getcwd(), gl,
                               None if outputs is None else [os.fspath(p) for p in outputs], int(width or 0),
                               int(height or 0), -1 if timestep is None else int(timestep), dtype, bool(cloud_layer))


class Renderer:
    """A renderer kept between frames: one GL context, the uploaded volume and the deep light map.

        with nephele.Renderer(ds, scene, gl="egl", width=960, height=540) as r:
            a = r.render()                                        # the scene as nephele.render renders it
            b = r.render(camera={"preset": "top"})                # only the ray cast runs again
            c = r.render(sun={"azimuth_deg": 90, "elevation_deg": 20})   # the light map is rebuilt
            d = r.render(time=1)                                  # a new volume and light map

    dataset, scene, gl, width, height, timestep: as for render(). Each render() call changes what
    it is given and keeps the rest from the previous call:
    time:    a timestep index (a fraction blends the two neighbouring timesteps, as `nephele
             animate` does: the scene's animation.interpolation, by default carried along their
             winds), or an ISO 8601 UTC time matching one of the dataset's times;
    camera:  a dict of the scene file's "camera" keys, replacing the camera section;
    sun:     a dict of the scene file's "sun" keys, replacing the sun section ({"from_time": true}
             follows the timestep's time; a fractional time takes the earlier timestep's);
    outputs, dtype, cloud_layer: as for render() (outputs: this frame's files; without them the
             scene's output.paths are written).
    The frame equals nephele.render of the same scene and timestep, byte for byte on the same GL
    backend; the volume frame (preset framing, georeference) is the first rendered timestep's, as
    in `nephele animate`. stats(): what the last frame rebuilt and counters since the start.
    close() (or the end of a `with` block) frees the GL context; use it from one thread at a time."""

    def __init__(self, dataset=None, scene=None, *, gl="auto", width=None, height=None, timestep=None):
        self._aliases = dataset._aliases if dataset is not None else {}
        self._dataset = dataset  # keeps from_xarray's temporary file alive
        if scene is None and dataset is not None:
            scene = quick_look(dataset, width=width or 1920, height=height or 1080)
        with _named_errors(self._aliases):
            self._handle = _nephele.Renderer(None if dataset is None else dataset._handle, *_scene_args(scene),
                                             os.getcwd(), gl, int(width or 0), int(height or 0),
                                             -1 if timestep is None else int(timestep))

    def render(self, *, time=None, camera=None, sun=None, outputs=None, dtype="float32", cloud_layer=False):
        time_index, time_utc = float("nan"), ""
        if isinstance(time, str):
            time_utc = time
        elif time is not None:
            time_index = float(time)
        overrides = {k: v for k, v in (("camera", camera), ("sun", sun)) if v is not None}
        with _named_errors(self._aliases):
            return self._handle.render(time_index, time_utc, json.dumps(overrides), camera is not None, sun is not None,
                                       None if outputs is None else [os.fspath(p) for p in outputs], dtype,
                                       bool(cloud_layer))

    def stats(self):
        """The last frame's volume_changed, dlm_rebuilt, time_index and *_ms timings; since the
        start: volume_uploads, dlm_builds, dlm_reuses, timestep_decodes (model files: conversions)."""
        return self._handle.stats()

    def close(self):
        self._handle.close()

    @property
    def closed(self):
        return self._handle.closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        return f"<nephele.Renderer {'closed' if self.closed else 'open'}>"


def quick_look(dataset, *, width=1920, height=1080):
    """The scene `nephele render FILE` renders without a scene file (README.md; src/engine/quick_look.h), as a dict:
    the oblique preset on the whole domain, the sun of the data's time and place (else a fixed
    afternoon sun), Blue Marble under georeferenced data, a height exaggeration for the domain's
    scale, broadcast quality. render() and Renderer use it when given no scene; edit it and pass
    it on to change a key. Reads the dataset's first timestep."""
    path = dataset._handle.path
    on_disk = not dataset._aliases and os.path.exists(path)  # arrays and xarray Datasets: no data.path
    with _named_errors(dataset._aliases):
        return json.loads(_nephele.quick_look(dataset._handle, path if on_disk else "", int(width), int(height)))


def _scene_args(scene):
    """(scene_path, scene_text, scene_name) of a scene dict, JSON file path or None."""
    if scene is None:
        return "", "{}", "<scene dict>"
    if isinstance(scene, dict):
        return "", json.dumps(scene), "<scene dict>"
    return os.fspath(scene), "", "<scene dict>"


def _extinction_from_xarray(dataset, names, label):
    ice, water = (dataset[n] for n in names)
    if ice.dims != water.dims or len(ice.dims) not in (3, 4):
        raise InputError(f"{label}: {names[0]} {ice.dims} and {names[1]} {water.dims}: expected the same "
                         "dimensions, (z, y, x) or (time, z, y, x)")
    z_name, y_name, x_name = ice.dims[-3:]
    axes = {}
    for dim in (z_name, y_name, x_name):
        if dim not in dataset.coords or dataset[dim].size < 2:
            raise InputError(f"{label}: {names[0]}: dimension {dim} has no coordinate of at least 2 values, "
                             "expected the centres of the grid's cells")
        axes[dim] = dataset[dim].values.astype("float64")
    step = {d: float(a[1] - a[0]) for d, a in axes.items()}
    for dim, a in axes.items():
        spacing = a[1:] - a[:-1]
        if not (step[dim] > 0 and abs(spacing - step[dim]).max() <= 1e-6 * abs(step[dim])):
            raise InputError(f"{label}: coordinate {dim} is not increasing with a uniform spacing "
                             f"(from {spacing.min()} to {spacing.max()}), expected a regular grid")
    times = None
    if len(ice.dims) == 4 and ice.dims[0] in dataset.coords:
        times = [str(t)[:19] + "Z" for t in dataset[ice.dims[0]].values.astype("datetime64[s]")]
    terrain = dataset["terrain_height_m"].values if "terrain_height_m" in dataset.variables else None
    return from_extinction(ice.values, water.values, terrain_height_m=terrain, dx=step[x_name], dy=step[y_name], dz_m=step[z_name],
                           z_bottom_m=axes[z_name][0] - step[z_name] / 2, proj=dataset.attrs.get("proj", ""),
                           x0=axes[x_name][0], y0=axes[y_name][0],
                           geographic=bool(dataset.attrs.get("geographic", False)), times_utc=times, name=label)


@contextlib.contextmanager
def _named_errors(aliases):
    """Errors about a temporary file name what it stands for (the xarray Dataset)."""
    try:
        yield
    except Error as e:
        text = str(e)
        renamed = text
        for path, label in aliases.items():
            renamed = renamed.replace(path, label)
        if renamed == text:
            raise
        raise type(e)(renamed) from None
