#!/usr/bin/env python3
"""A generated DEM for docs/terrain.md's "A user DEM" picture (no real DEM may be downloaded).

Writes an ESRI ASCII grid (GDAL's AAIGrid driver) in EPSG:4326 with its .prj: a ridge line along
Cuba, south-west of issue 13's coarse storm (nephele-gen wrf --case storm: Lambert conformal,
72 x 64 columns of 10 km centred at 75 W, 25 N), beyond the model's grid, and nodata elsewhere, so
that inside the grid the model's own HGT stays (the DEM wins only where it has data;
docs/terrain.md).

usage: make-ridge-dem.py OUT.asc
"""
import math
import sys

# A Sierra Maestra-like ridge line along Cuba's spine, south-west of the storm's grid: the crest
# runs from (84 W, 22.4 N) to (74.4 W, 20.1 N) with peaks of 700-2000 m (Pico Turquino: 1974 m),
# Gaussian across it (sigma 0.15 deg); nodata where lower than 5 m (the sea: like a land DEM).
CREST = ((-84.0, 22.4), (-74.4, 20.1))
PEAKS = [(-83.6, 700.0), (-82.0, 900.0), (-80.1, 1100.0), (-79.0, 1400.0), (-77.3, 1600.0), (-76.6, 2000.0),
         (-75.5, 1500.0), (-74.7, 1200.0)]


def height(lon, lat):
    (l0, p0), (l1, p1) = CREST
    f = (lon - l0) / (l1 - l0)
    if f < -0.05 or f > 1.05:
        return 0.0
    crest_lat = p0 + f * (p1 - p0) + 0.12 * math.sin(lon * 2.1)
    along = sum(h * math.exp(-((lon - pl) ** 2) / (2 * 0.45 ** 2)) for pl, h in PEAKS)
    return min(along, 2000.0) * math.exp(-((lat - crest_lat) ** 2) / (2 * 0.15 ** 2))


def main():
    out = sys.argv[1]
    lon0, lat1, step = -86.0, 35.0, 0.02
    w, h = 1100, 900
    nodata = -9999
    with open(out, "w") as f:
        f.write(f"ncols {w}\nnrows {h}\nxllcorner {lon0}\nyllcorner {lat1 - h * step}\ncellsize {step}\n"
                f"NODATA_value {nodata}\n")
        for j in range(h):
            lat = lat1 - (j + 0.5) * step
            row = []
            for i in range(w):
                z = height(lon0 + (i + 0.5) * step, lat)
                row.append(f"{z:.1f}" if z > 5.0 else str(nodata))
            f.write(" ".join(row) + "\n")
    with open(out[:-4] + ".prj", "w") as f:
        f.write('GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
                'PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]]')


if __name__ == "__main__":
    main()
