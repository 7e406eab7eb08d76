#include "wrf_alpine.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <queue>
#include <utility>

namespace nph::datagen {
namespace {

constexpr double kPi = std::numbers::pi;
/// The ambient wind blows towards 20° north of east: anvils and the lee deck lie that way.
constexpr double kDownwind_rad = 20.0 * kPi / 180.0;

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
double layer(double z, double lo, double hi, double edge) {
  return smoothstep(lo - edge, lo, z) * (1.0 - smoothstep(hi, hi + edge, z));
}

/// Distance [km] from (x, y) to the polyline and the arc-length fraction of its nearest point.
void nearestOnLine(const AlpineValley& v, double x, double y, double& dist, double& frac) {
  double total = 0.0;
  for (std::size_t p = 1; p < v.x_km.size(); ++p)
    total += std::hypot(v.x_km[p] - v.x_km[p - 1], v.y_km[p] - v.y_km[p - 1]);
  dist = 1e30;
  frac = 0.0;
  double s = 0.0;
  for (std::size_t p = 1; p < v.x_km.size(); ++p) {
    const double ax = v.x_km[p - 1], ay = v.y_km[p - 1], bx = v.x_km[p], by = v.y_km[p];
    const double len = std::hypot(bx - ax, by - ay);
    const double t =
        len > 0.0 ? std::clamp(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / (len * len), 0.0, 1.0) : 0.0;
    const double d = std::hypot(x - (ax + t * (bx - ax)), y - (ay + t * (by - ay)));
    if (d < dist) {
      dist = d;
      frac = total > 0.0 ? (s + t * len) / total : 0.0;
    }
    s += len;
  }
}

/// The floor at an arc-length fraction: steeper near the head (a power below 1), strictly falling.
double floorAt(const AlpineValley& v, double frac) {
  return v.head_m + (v.mouth_m - v.head_m) * std::pow(std::clamp(frac, 0.0, 1.0), 0.8);
}

}  // namespace

double AlpineTerrain::axisYkm(double x_km) const {
  const double ly = (ny - 1) * dx_km;
  return 0.5 * ly + 16.0 * std::sin(2.0 * kPi * x_km / 300.0 + 0.6);
}

AlpineSample sampleAlpineTerrain(const AlpineTerrain& t, const ValueNoise& noise, double x, double y, int octaves) {
  const double d = y - t.axisYkm(x);
  const double plain = 180.0 + 270.0 * smoothstep(-40.0, 40.0, d);
  const double crest = 2750.0 + 900.0 * (noise.fbm(x / 70.0, 3.1, 0.5, 2) - 0.5);
  const double belt =
      (1.0 - smoothstep(30.0, 105.0, std::abs(d))) * (0.75 + 0.5 * noise.fbm(x / 45.0 + 10.0, y / 45.0 + 10.0, 1.7, 3));
  const double env = plain + crest * belt;
  AlpineSample a;
  double h = env, floor = env, wall = 1.0;
  for (const AlpineValley& v : t.valleys) {
    const double reach = v.floor_half_width_km + v.wall_width_km;
    if (x < v.x_min - reach || x > v.x_max + reach || y < v.y_min - reach || y > v.y_max + reach) continue;
    double dist = 0.0, frac = 0.0;
    nearestOnLine(v, x, y, dist, frac);
    if (dist > v.floor_half_width_km + v.wall_width_km) continue;
    const double f = floorAt(v, frac);
    if (f >= env) continue;
    const double s = smoothstep(v.floor_half_width_km, v.floor_half_width_km + v.wall_width_km, dist);
    const double hv = f + (env - f) * s;
    if (hv < h) {
      h = hv;
      floor = f;
      wall = s;
      a.fog = v.fog ? 1 : 0;
    }
  }
  // Ridged relief on the walls and crests (none on the floors, little on the foreland).
  const double ridged =
      std::pow(1.0 - std::abs(2.0 * noise.fbm(x / 16.0 + 30.0, y / 16.0 + 30.0, 7.3, octaves) - 1.0), 2.0);
  const double mountain = std::clamp((env - plain) / 2000.0, 0.0, 1.0);
  a.height_m = std::max(floor, h + wall * (0.15 + 0.85 * mountain) * (1100.0 * ridged - 300.0));
  a.envelope_m = env;
  a.floor_m = floor;
  a.wall = wall;
  return a;
}

// The range: a crest envelope (a belt of half-width ~60 km along the divide, its crest 2.3–3.2 km
// varying along the range, over a foreland at 180 m in the south and 450 m in the north) into
// which valleys are cut: two longitudinal valleys either side of the divide (the northern one
// draining west, the southern one east, as the Rhône and the Drava do), tributaries from the divide
// joining them, and short valleys on the outer flanks draining to the foreland. A valley's cross
// profile is a U: a flat floor, then walls that rise to the envelope (Alpine glacial troughs). The
// walls and the crests carry ridged noise (Musgrave's ridged multifractal, Ebert et al. 2003
// §16.4), the floors none, so every floor is a connected line that falls from its head to its
// mouth and the water has somewhere to go.
AlpineTerrain alpineTerrain(int nx, int ny, double dx_m, const ValueNoise& noise) {
  AlpineTerrain t;
  t.nx = nx;
  t.ny = ny;
  t.dx_km = dx_m / 1000.0;
  const double lx = (nx - 1) * t.dx_km;
  auto line = [&](double x0, double x1, int n, auto&& y_of_x) {
    AlpineValley v;
    for (int p = 0; p <= n; ++p) {
      const double x = x0 + (x1 - x0) * p / n;
      v.x_km.push_back(x);
      v.y_km.push_back(y_of_x(x));
    }
    return v;
  };
  // Longitudinal valleys, 30 km either side of the divide, beyond the domain at both ends: the
  // northern one drains west (as the Rhône does), the southern one east (as the Drava does).
  AlpineValley north =
      line(lx + 10.0, -10.0, 90, [&](double x) { return t.axisYkm(x) + 32.0 + 5.0 * std::sin(x / 27.0); });
  north.head_m = 1500.0;
  north.mouth_m = 420.0;
  north.floor_half_width_km = 3.0;
  north.wall_width_km = 9.0;
  AlpineValley south =
      line(-10.0, lx + 10.0, 90, [&](double x) { return t.axisYkm(x) - 30.0 + 5.0 * std::sin(x / 31.0 + 1.0); });
  south.head_m = 1350.0;
  south.mouth_m = 190.0;
  south.floor_half_width_km = 3.0;
  south.wall_width_km = 9.0;
  south.fog = true;
  t.valleys = {north, south};
  // Tributaries from near the divide into the longitudinal valleys: their mouths are points of the
  // main valley's line and their floors end on its floor there.
  auto tributary = [&](const AlpineValley& main, double x_head, double y_head, double x_mouth, double head_m) {
    double d = 0.0, frac = 0.0;
    // The mouth: the main line's point at x_mouth.
    double y_mouth = main.y_km.front();
    for (std::size_t p = 1; p < main.x_km.size(); ++p) {
      const double a = main.x_km[p - 1], b = main.x_km[p];
      if ((x_mouth - a) * (x_mouth - b) <= 0.0 && a != b) {
        y_mouth = main.y_km[p - 1] + (main.y_km[p] - main.y_km[p - 1]) * (x_mouth - a) / (b - a);
        break;
      }
    }
    nearestOnLine(main, x_mouth, y_mouth, d, frac);
    AlpineValley v;
    for (int p = 0; p <= 8; ++p) {
      const double f = p / 8.0;
      v.x_km.push_back(x_head + (x_mouth - x_head) * f + 2.0 * std::sin(kPi * f));
      v.y_km.push_back(y_head + (y_mouth - y_head) * f);
    }
    v.head_m = head_m;
    v.mouth_m = floorAt(main, frac);
    v.floor_half_width_km = 2.3;  // the nearest mass point of a 3 km grid is never farther than 2.12 km
    v.wall_width_km = 8.0;
    v.fog = main.fog;
    return v;
  };
  // Every 24 km (jittered) on both sides of both longitudinal valleys: from near the divide and
  // from the outer crests, 25–30 km long, slanting downstream.
  for (int k = 0; k < 22; ++k) {
    for (int side = 0; side < 4; ++side) {
      const double xm = 6.0 + 24.0 * k + 12.0 * (side % 2) + 10.0 * (noise.hash(k, side, 77) - 0.5);
      if (xm < 6.0 || xm > lx - 6.0) continue;
      const bool into_north = side < 2, from_divide = side % 2 == 0;
      const AlpineValley& main = t.valleys[into_north ? 0 : 1];
      // The main valley drains west (north) or east (south): heads lie upstream of the mouth.
      const double upstream = into_north ? 1.0 : -1.0;
      const double xh = xm + upstream * (5.0 + 6.0 * noise.hash(k, side, 78));
      const double yh = t.axisYkm(xh) + (into_north ? 1.0 : -1.0) * (from_divide ? 4.0 : 60.0);
      const double head = (from_divide ? 2150.0 : 1700.0) + 300.0 * noise.hash(k, side, 79);
      t.valleys.push_back(tributary(main, xh, yh, xm, head));
    }
  }
  // Outer flanks: valleys from the outer crests to the foreland, every 30 km.
  for (int k = 0; k < 17; ++k) {
    for (int side = 0; side < 2; ++side) {
      const double xo = 10.0 + 30.0 * k + 15.0 * side + 10.0 * (noise.hash(k, side, 80) - 0.5);
      if (xo < 6.0 || xo > lx - 6.0) continue;
      const double sign = side == 0 ? 1.0 : -1.0;
      const double drift = 8.0 * (noise.hash(k, side, 81) - 0.5);
      AlpineValley v;
      for (int p = 0; p <= 8; ++p) {
        const double f = p / 8.0;
        v.x_km.push_back(xo + drift * f + 2.5 * std::sin(3.0 * f + xo));
        v.y_km.push_back(t.axisYkm(xo) + sign * (64.0 + 56.0 * f));
      }
      v.head_m = 1500.0 + 300.0 * noise.hash(k, side, 82);
      v.mouth_m = side == 0 ? 430.0 : 170.0;
      v.floor_half_width_km = 2.3;
      v.wall_width_km = 7.0;
      t.valleys.push_back(v);
    }
  }

  for (AlpineValley& v : t.valleys) {
    v.x_min = *std::min_element(v.x_km.begin(), v.x_km.end());
    v.x_max = *std::max_element(v.x_km.begin(), v.x_km.end());
    v.y_min = *std::min_element(v.y_km.begin(), v.y_km.end());
    v.y_max = *std::max_element(v.y_km.begin(), v.y_km.end());
  }
  const std::size_t n2 = std::size_t(nx) * std::size_t(ny);
  t.height_m.assign(n2, 0.0);
  t.envelope_m.assign(n2, 0.0);
  t.floor_m.assign(n2, 0.0);
  t.wall.assign(n2, 1.0);
  t.fog.assign(n2, 0);
  tbb::parallel_for(0, ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const AlpineSample a = sampleAlpineTerrain(t, noise, i * t.dx_km, j * t.dx_km, 4);
      t.height_m[c] = a.height_m;
      t.envelope_m[c] = a.envelope_m;
      t.floor_m[c] = a.floor_m;
      t.wall[c] = a.wall;
      t.fog[c] = a.fog;
    }
  });
  // Hydrological conditioning: the ridged relief leaves small closed bowls on the walls, which
  // real eroded terrain does not have. Priority-flood with an epsilon gradient (Barnes, Lehman and
  // Mulla 2014, Computers & Geosciences 62, Algorithm 3) raises each bowl to its spill height
  // plus 0.5 m per cell, so every mass point drains to the domain's edge; the valley floors, which
  // fall everywhere already, stay as they are.
  {
    using Entry = std::pair<double, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    std::vector<char> closed(n2, 0);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        if (i == 0 || j == 0 || i == nx - 1 || j == ny - 1) {
          const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
          closed[c] = 1;
          open.push({t.height_m[c], c});
        }
    while (!open.empty()) {
      const auto [h, c] = open.top();
      open.pop();
      const int i = static_cast<int>(c % std::size_t(nx)), j = static_cast<int>(c / std::size_t(nx));
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ii = i + di, jj = j + dj;
          if (ii < 0 || jj < 0 || ii >= nx || jj >= ny) continue;
          const std::size_t n = std::size_t(jj) * std::size_t(nx) + std::size_t(ii);
          if (closed[n]) continue;
          closed[n] = 1;
          t.height_m[n] = std::max(t.height_m[n], h + 0.5);
          open.push({t.height_m[n], n});
        }
    }
  }
  return t;
}

// The storm, column by column (grid kilometres):
// - towers: nine places along the range (from 100 km east of its west end, 40 km apart), each on the highest mass point
// within 9 km along and
//   22 km across the divide (a crest), some pushed 0–6 km down the windward (southern) slope, a
//   fifth of them left empty; radius 4.5–8 km, domed tops at 9.5–12.5 km, bases 250 m above the
//   ground and no lower than 2 km; a second row of congestus (tops 6.5–9 km) on the southern
//   foothills;
// - anvils: every tower above 10.3 km spreads an anvil downwind (east-north-east), an ellipse of
//   50 × 26 km centred 30 km downwind, 2.2 km deep at the tower and thinning to its rim;
// - the lee deck: altostratus/nimbostratus north-east of the range (tops 6–7.5 km, bases 3.6–5 km),
//   broken where its noise is low;
// - shallow cumulus over the slopes (not the floors, not the foreland) of the central and eastern
//   range (the western third is in drier air upstream): on a jittered 7 km lattice,
//   bases 400 m above the ground under them, 0.9–2.5 km deep;
// - fog in the southern valley and its tributaries where their floor is below 1000 m: a flat top
//   260–380 m above the floor (a valley inversion), so the walls rise out of it.
//
// The life cycle (alpineStage) moves and ages this mature storm: every cell is displaced by
// stage.shift (found at its mature place first, so the crests it grew over stay the same), a
// young tower (growth 0) is 3.5 km lower, 25 % narrower and holds 40 % less condensate and has no
// anvil yet, a decaying one (decay 1) is 2.5 km lower with 65 % less; an anvil's upwind edge stays
// at its tower while its downwind edge runs ahead with the wind at its height (anvil_age_h).
AlpineColumns alpineColumns(const AlpineTerrain& t, const ValueNoise& noise, const AlpineStage& stage) {
  const int nx = t.nx, ny = t.ny;
  const std::size_t n2 = std::size_t(nx) * std::size_t(ny);
  const double dx = t.dx_km, lx = (nx - 1) * dx, ly = (ny - 1) * dx;
  AlpineColumns col;
  for (std::vector<float>* v :
       {&col.tower, &col.tower_top_km, &col.tower_base_km, &col.tower_depth, &col.anvil, &col.anvil_top_km,
        &col.anvil_base_km, &col.deck, &col.deck_top_km, &col.deck_base_km, &col.fog_top_m}) {
    v->assign(n2, 0.0f);
  }
  auto hgtAt = [&](double x, double y) {
    const int i = std::clamp(static_cast<int>(std::lround(x / dx)), 0, nx - 1);
    const int j = std::clamp(static_cast<int>(std::lround(y / dx)), 0, ny - 1);
    return t.height_m[std::size_t(j) * std::size_t(nx) + std::size_t(i)];
  };
  struct Cell {
    double x, y, radius, top, strength, base_offset_km;
    bool anvil;
    double anvil_top = 0.0, anvil_strength = 0.0;  ///< the mature tower's: the anvil stays at its level
    double claim = strength;  ///< which cell a column belongs to where they overlap: the mature strength
  };
  std::vector<Cell> cells;
  for (int k = 0; k < 9; ++k) {
    if (noise.hash(k, 1, 91) < 0.2) continue;
    const double xk = 100.0 + 40.0 * k + 12.0 * (noise.hash(k, 2, 91) - 0.5);
    double best = -1.0, bx = xk, by = t.axisYkm(xk);
    for (double x = xk - 9.0; x <= xk + 9.0; x += dx) {
      for (double y = t.axisYkm(x) - 22.0; y <= t.axisYkm(x) + 22.0; y += dx) {
        const double h = hgtAt(x, y);
        if (h > best) {
          best = h;
          bx = x;
          by = y;
        }
      }
    }
    by -= 6.0 * noise.hash(k, 3, 91);
    const double h = noise.hash(k, 4, 91);
    const double top = 9.5 + 3.0 * std::pow(h, 1.3);
    const double strength = 0.6 + 0.4 * noise.hash(k, 6, 91);
    const double young = 1.0 - stage.growth;
    cells.push_back({bx + stage.shift_x_km, by + stage.shift_y_km,
                     (4.5 + 3.5 * noise.hash(k, 5, 91)) * (1.0 - 0.25 * young), top - 3.5 * young - 2.5 * stage.decay,
                     strength * (1.0 - 0.4 * young) * (1.0 - 0.65 * stage.decay), 0.25,
                     top > 10.3 && stage.growth > 0.0, top, strength * (1.0 - 0.4 * stage.decay), strength});
  }
  for (int k = 0; k < 4; ++k) {
    const double x = 190.0 + 80.0 * k + 20.0 * (noise.hash(k, 7, 91) - 0.5);
    const double y = t.axisYkm(x) - 44.0 + 8.0 * (noise.hash(k, 8, 91) - 0.5);
    const double young = 1.0 - stage.growth;
    cells.push_back({x + stage.shift_x_km, y + stage.shift_y_km,
                     (3.5 + 2.0 * noise.hash(k, 9, 91)) * (1.0 - 0.25 * young),
                     6.5 + 2.5 * noise.hash(k, 10, 91) - 2.0 * young - 2.0 * stage.decay,
                     0.5 * (1.0 - 0.4 * young) * (1.0 - 0.65 * stage.decay), 0.25, false, 0.0, 0.0, 0.5});
  }
  // Cumulus over the slopes.
  constexpr double kSpacing = 7.0;
  for (int q = 0; q * kSpacing < ly; ++q) {
    for (int p = 0; p * kSpacing < lx; ++p) {
      const double x = (p + noise.hash(p, q, 92)) * kSpacing, y = (q + noise.hash(p, q, 93)) * kSpacing;
      const int i = std::clamp(static_cast<int>(std::lround(x / dx)), 0, nx - 1);
      const int j = std::clamp(static_cast<int>(std::lround(y / dx)), 0, ny - 1);
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const double mountain = std::clamp((t.envelope_m[c] - 450.0) / 2000.0, 0.0, 1.0);
      if (t.wall[c] < 0.25 || mountain < 0.3 || noise.hash(p, q, 94) > 0.4 * smoothstep(90.0, 150.0, x)) continue;
      const double h = noise.hash(p, q, 95);
      cells.push_back({x + stage.shift_x_km, y + stage.shift_y_km, 1.8 + 1.2 * h, 0.0,
                       0.35 + 0.25 * noise.hash(p, q, 96), 0.9 + 1.6 * h, false});
    }
  }
  // Where cells overlap the column is the one with the stronger claim (the mature strength, so a
  // young or collapsing tower is not holed by the cumulus around it).
  std::vector<float> claim(n2, 0.0f);
  for (const Cell& s : cells) {
    const double reach = 2.2 * s.radius / dx;
    const double gi = s.x / dx, gj = s.y / dx;
    const int i0 = std::max(0, static_cast<int>(std::ceil(gi - reach)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor(gi + reach)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(gj - reach)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor(gj + reach)));
    const bool cumulus = s.top == 0.0;
    // A cumulus's base is the condensation level over the ground under its centre; a tower's base
    // follows the ground under each column (no lower than 2 km).
    const double cu_base = hgtAt(s.x, s.y) / 1000.0 + 0.4;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
        // Towers: a super-Gaussian (steep sides, a broad core); cumulus: a Gaussian.
        const double r = std::hypot(i * dx - s.x, j * dx - s.y) / s.radius;
        const double g = cumulus ? std::exp(-r * r) : std::exp(-r * r * r * r);
        if (s.claim * g <= double(claim[c])) continue;
        claim[c] = static_cast<float>(s.claim * g);
        const double base = cumulus ? std::max(cu_base, t.height_m[c] / 1000.0 + 0.1)
                                    : std::max(2.0, t.height_m[c] / 1000.0 + s.base_offset_km);
        const double summit = cumulus ? cu_base + s.base_offset_km : s.top;
        col.tower[c] = static_cast<float>(s.strength * g);
        col.tower_base_km[c] = static_cast<float>(base);
        col.tower_top_km[c] = static_cast<float>(base + (summit - base) * std::pow(g, 0.35));
        col.tower_depth[c] = static_cast<float>(cumulus ? 0.0 : smoothstep(4.0, 8.0, summit));
      }
    }
  }
  for (std::size_t c = 0; c < n2; ++c) {
    if (col.tower[c] < 0.05f || col.tower_top_km[c] < col.tower_base_km[c] + 0.3f) col.tower[c] = 0.0f;
  }
  const double ca = std::cos(kDownwind_rad), sa = std::sin(kDownwind_rad);
  tbb::parallel_for(0, ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * std::size_t(nx) + std::size_t(i);
      const double x = i * dx, y = j * dx;
      // Anvils.
      for (const Cell& s : cells) {
        if (!s.anvil) continue;
        // The anvil lengthens downwind: its upwind edge (20 km upwind of the centre of the tower)
        // moves with the tower, its downwind edge with the wind at its mid level, 1.2 km under
        // the mature top — (u(z) − u_steering) · age longer, the centre and the half-length
        // each half of that further downwind. Its texture moves with the wind too.
        double us = 0.0, vs = 0.0, ua = 0.0, va = 0.0;
        alpineSteeringWind(us, vs);
        alpineWind(1000.0 * (s.anvil_top - 1.2), ua, va);
        const double spread_km = 0.5 * 3.6 * (std::hypot(ua, va) - std::hypot(us, vs)) * stage.anvil_age_h;
        const double ax = x - (s.x + (30.0 + spread_km) * ca), ay = y - (s.y + (30.0 + spread_km) * sa);
        const double along = ax * ca + ay * sa, across = -ax * sa + ay * ca;
        const double tx = x - stage.shift_x_km - 2.0 * spread_km * ca, ty = y - stage.shift_y_km - 2.0 * spread_km * sa;
        const double e = std::hypot(along / (50.0 + spread_km), across / 26.0) *
                         (0.85 + 0.3 * noise.fbm(tx / 20.0 + 60.0, ty / 20.0 + 60.0, s.anvil_top, 2));
        const double a = s.anvil_strength * (1.0 - smoothstep(0.55, 1.0, e));
        if (a <= double(col.anvil[c])) continue;
        const double rim = smoothstep(0.3, 1.0, e);
        col.anvil[c] = static_cast<float>(a);
        col.anvil_top_km[c] = static_cast<float>(s.anvil_top - 0.3 - 0.8 * rim);
        // A decaying anvil thins from below (its ice sublimating into drier air).
        col.anvil_base_km[c] = static_cast<float>(s.anvil_top - 2.2 + 1.3 * rim + 0.3 * stage.decay);
      }
      // The lee deck (moved as a whole by the wind at its mid level: the pattern at (x, y) is the
      // mature one at (x, y) − shift).
      {
        const double dx_km = x - stage.deck_shift_x_km, dy_km = y - stage.deck_shift_y_km;
        const double ax = dx_km - 0.72 * lx, ay = dy_km - (t.axisYkm(0.72 * lx) + 55.0);
        const double along = ax * ca + ay * sa, across = -ax * sa + ay * ca;
        const double e = std::hypot(along / 140.0, across / 70.0);
        const double n = noise.fbm(dx_km / 40.0 + 20.0, dy_km / 40.0 + 20.0, 4.4, 3);
        col.deck[c] = static_cast<float>((1.0 - smoothstep(0.6, 1.0, e)) * smoothstep(0.35, 0.55, n));
        col.deck_top_km[c] = static_cast<float>(6.0 + 1.5 * noise.fbm(dx_km / 60.0, dy_km / 60.0, 5.5, 2));
        col.deck_base_km[c] = static_cast<float>(3.6 + 0.6 * noise.fbm(dx_km / 50.0, dy_km / 50.0, 6.6, 2) +
                                                 1.0 * smoothstep(0.5, 1.0, e));
      }
      // Valley fog.
      if (t.fog[c] && t.floor_m[c] < 1000.0) {
        const double top = t.floor_m[c] + 260.0 + 120.0 * noise.fbm(x / 25.0, y / 25.0, 8.8, 2);
        if (t.height_m[c] < top - 40.0 && col.tower[c] < 0.2f) col.fog_top_m[c] = static_cast<float>(top);
      }
    }
  });
  return col;
}

AlpinePoint alpinePoint(const AlpineColumns& col, std::size_t c, double z_m, double terrain_m, double temperature_k) {
  AlpinePoint p;
  const double zk = z_m / 1000.0;
  const double tower = col.tower[c], depth = col.tower_depth[c];
  const double base = col.tower_base_km[c], top = col.tower_top_km[c];
  const double core = tower * layer(zk, base, top, 0.3);
  const double anvil = double(col.anvil[c]) * layer(zk, col.anvil_base_km[c], col.anvil_top_km[c], 0.3);
  const double deck = double(col.deck[c]) * layer(zk, col.deck_base_km[c], col.deck_top_km[c], 0.25);
  const double fog_top = col.fog_top_m[c];
  const double fog = fog_top > 0.0 ? 1.0 - smoothstep(fog_top - 80.0, fog_top, z_m) : 0.0;
  const bool warm = temperature_k > kFreezingPoint_k;
  const double freezing_mix = smoothstep(kFreezingPoint_k - 25.0, kFreezingPoint_k - 2.0, temperature_k);
  // Cumulus over the slopes are partly sub-grid at 3 km: a tenth of a tower's cloud water.
  const double liquid = 0.1 + 0.9 * depth;
  p.q_cloud = (1.5e-3 * core * liquid +
               1.0e-4 * double(col.deck[c]) * layer(zk, col.deck_base_km[c], double(col.deck_base_km[c]) + 0.8, 0.2)) *
                  freezing_mix +
              2.0e-4 * fog;
  p.q_rain = (2.5e-3 * tower * depth * std::min(1.0, 3.0 * tower) + 1.5e-4 * double(col.deck[c])) *
             layer(zk, -1.0, 4.0, 0.6) * (warm ? 1.0 : 0.2);
  p.q_graupel = 1.2e-3 * tower * depth * layer(zk, 4.5, std::min(top, 9.5), 0.8);
  if (!warm) {
    p.q_ice =
        4.0e-4 * core * depth * smoothstep(6.0, 9.0, zk) + 1.2e-4 * anvil + 4.0e-5 * deck * smoothstep(5.0, 7.0, zk);
    p.q_snow = 6.0e-4 * core * depth * smoothstep(5.0, 7.0, zk) + 2.2e-4 * deck + 3.0e-5 * anvil;
  }
  const double updraft = std::sin(kPi * std::clamp((zk - base) / std::max(top - base, 0.5), 0.0, 1.0));
  p.w_m_per_s = tower * (10.0 * depth + 2.0 * (1.0 - depth)) * updraft + 0.3 * deck + 0.2 * anvil -
                2.0 * tower * depth * layer(zk, terrain_m / 1000.0, base, 0.3);
  // TKE: a mixed boundary layer following the ground (stable, nearly still, in the fog), the cores,
  // the anvils' and the deck's turbulence.
  p.tke_m2_per_s2 = (fog_top > 0.0 ? 0.05 : 0.5) * (1.0 - smoothstep(600.0, 1600.0, z_m - terrain_m)) + 4.0 * core +
                    0.8 * anvil + 0.5 * deck + 0.02 * fog;
  return p;
}

void alpineWind(double z_m, double& u, double& v) {
  const double zk = std::clamp(z_m / 1000.0, 0.0, 16.0);
  const double speed = 6.0 + 1.5 * zk;
  u = speed * std::cos(kDownwind_rad);
  v = speed * std::sin(kDownwind_rad);
}

void alpineSteeringWind(double& u, double& v) {
  // The 0–6 km mean wind (Bunkers et al. 2000, Weather and Forecasting 15, the non-pressure-
  // weighted mean that ordinary cells move with): alpineWind is linear in height, so its mean over
  // 0–6 km is its value at 3 km.
  alpineWind(3000.0, u, v);
}

// The life cycle of an ordinary cell (Byers and Braham 1949, The Thunderstorm: cumulus, mature
// and dissipating stages, each of the order of half an hour to an hour; a cell's top rises by
// several kilometres in its cumulus stage, the anvil spreads at the equilibrium level, under the
// tropopause, once the top reaches it). Step 1 is the mature storm (the single timestep), the
// cells at their mature places; step t is (t − 1) hours from it.
AlpineStage alpineStage(int t, int ntimes) {
  AlpineStage s;
  if (ntimes <= 1) return s;
  s.life_cycle = true;
  const double hours = t - 1.0;
  double us = 0.0, vs = 0.0;
  alpineSteeringWind(us, vs);
  s.shift_x_km = 3.6 * us * hours;
  s.shift_y_km = 3.6 * vs * hours;
  // The deck (bases 3.6–5 km, tops 6–7.5 km) moves with the wind at 5.3 km, its mean mid level.
  double ud = 0.0, vd = 0.0;
  alpineWind(5300.0, ud, vd);
  s.deck_shift_x_km = 3.6 * ud * hours;
  s.deck_shift_y_km = 3.6 * vd * hours;
  s.growth = t == 0 ? 0.0 : 1.0;
  s.anvil_age_h = std::max(0.0, hours);
  s.decay = ntimes >= 3 && t == ntimes - 1 ? 1.0 : 0.0;
  return s;
}

void alpineCloudWind(const AlpineColumns& col, std::size_t c, double z_m, double& u, double& v) {
  const double zk = z_m / 1000.0;
  const double in_tower = smoothstep(0.0, 0.1, double(col.tower[c])) *
                          layer(zk, double(col.tower_base_km[c]), double(col.tower_top_km[c]), 0.5);
  double us = 0.0, vs = 0.0;
  alpineSteeringWind(us, vs);
  u += in_tower * (us - u);
  v += in_tower * (vs - v);
  const double fog_top = col.fog_top_m[c];
  if (fog_top > 0.0) {
    const double calm = 1.0 - smoothstep(fog_top, fog_top + 300.0, z_m);
    u *= 1.0 - calm;
    v *= 1.0 - calm;
  }
}

}  // namespace nph::datagen
