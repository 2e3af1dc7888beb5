// Viridis, the perceptually uniform colour map of matplotlib, from a
// degree-6 polynomial fit per channel (max error below 1/255), tabulated once.

const C = [
  [0.2777273272234177, 0.005407344544966578, 0.3340998053353061],
  [0.1050930431085774, 1.404613529898575, 1.384590162594685],
  [-0.3308618287255563, 0.214847559468213, 0.09509516302823659],
  [-4.634230498983486, -5.799100973351585, -19.33244095627987],
  [6.228269936347081, 14.17993336680509, 56.69055260068105],
  [4.776384997670288, -13.74514537774601, -65.35303263337234],
  [-5.435455855934631, 4.645852612178535, 26.3124352495832],
];

/** 256 RGB triples, row-major in a Uint8ClampedArray of length 768. */
export const VIRIDIS = (() => {
  const lut = new Uint8ClampedArray(256 * 3);
  for (let i = 0; i < 256; i++) {
    const t = i / 255;
    for (let ch = 0; ch < 3; ch++) {
      let v = C[6][ch];
      for (let k = 5; k >= 0; k--) v = C[k][ch] + t * v;
      lut[3 * i + ch] = Math.round(255 * v);
    }
  }
  return lut;
})();

/** The colour at t in [0, 1] as a CSS string. */
export function viridisCss(t) {
  const i = 3 * Math.max(0, Math.min(255, Math.round(255 * t)));
  return `rgb(${VIRIDIS[i]}, ${VIRIDIS[i + 1]}, ${VIRIDIS[i + 2]})`;
}
