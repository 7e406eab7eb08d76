// Real spherical harmonics up to l = 4 (25 functions; issue 12, sixteenth session): the angular
// basis of the Monte Carlo radiance volume (glsl/dlm/radiance_volume.comp tallies c_lm = ∫ L Y_lm
// dω, glsl/render/clouds.comp reads J = Σ_l G_l Σ_m c_lm Y_lm back). The same functions, index and
// signs as the CPU twin reference::sphericalHarmonics (reference/mc_radiance_volume.cpp): index
// l² + l + m; Y_l0 = K_l0·P_l(z), Y_l±m = √2·K_lm·P̃_lm(z)·{Re, Im}(x + iy)^m with P̃_lm =
// P_lm / sin^m θ a polynomial in z (no Condon–Shortley phase), K_lm = √((2l + 1)/(4π)·(l − m)!/
// (l + m)!) (Green 2003, "Spherical harmonic lighting: the gritty details", §2). The recurrence
// is the CPU's, unrolled for l ≤ 4 in float.
const int kShCount = 25;

// K_lm (× √2 for m > 0) at index l² + l + m for m ≥ 0 (the m < 0 entries are the same as +m).
const float kShNorm[25] = float[25](
    0.28209479177387814,                                                                        //
    0.4886025119029200, 0.4886025119029199, 0.4886025119029200,                                //
    0.18209140509867985, 0.3641828101973597, 0.6307831305050401, 0.3641828101973597,           //
    0.18209140509867985,                                                                       //
    0.03933623932844291, 0.09635371475468515, 0.3046971996429772, 0.7463526651802308,          //
    0.3046971996429772, 0.09635371475468515, 0.03933623932844291,                              //
    0.005960340337611203, 0.016858388283618388, 0.063078313050504, 0.2676186174229157,         //
    0.8462843753216345, 0.2676186174229157, 0.063078313050504, 0.016858388283618388,           //
    0.005960340337611203);

// Y_lm(d) for l ≤ 4 of a unit vector d into y[l² + l + m].
void shBasis4(vec3 d, out float y[25]) {
  float z = d.z;
  float re = 1.0, im = 0.0;  // (x + iy)^m
  float pmm = 1.0;           // P̃_mm = (2m − 1)!!
  for (int m = 0; m <= 4; ++m) {
    if (m > 0) {
      float r = re * d.x - im * d.y;
      im = re * d.y + im * d.x;
      re = r;
      pmm *= float(2 * m - 1);
    }
    float pPrev = 0.0, p = pmm;
    for (int l = m; l <= 4; ++l) {
      if (l == m + 1) {
        pPrev = p;
        p = float(2 * m + 1) * z * pmm;
      } else if (l > m + 1) {
        float next = (float(2 * l - 1) * z * p - float(l + m - 1) * pPrev) / float(l - m);
        pPrev = p;
        p = next;
      }
      int c = l * l + l;
      float K = kShNorm[c + m];
      if (m == 0) {
        y[c] = K * p;
      } else {
        y[c + m] = K * p * re;
        y[c - m] = K * p * im;
      }
    }
  }
}
