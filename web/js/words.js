// The samplers in plain words, shown beside the method's control and in
// compare mode.

/** One line per sampler: what it is, in terms a newcomer can follow. */
export const SAMPLER_HINTS = {
  hrla: "HRLA, the paper's method: each chain has a position and a velocity, and a step draws both exactly from the Gaussian that the high-resolution Langevin dynamics reaches with the gradient held fixed over the step.",
  ula: "ULA, underdamped Langevin: the chains have momentum (a velocity slowed by friction); the position moves only through the velocity. HRLA without its gradient and noise on the position.",
  ola: "OLA, overdamped Langevin: no momentum; each step goes downhill by h·∇U and adds a random kick (Euler's method). HRLA without the velocity.",
};

/** Compare mode: the three at once. */
export const COMPARE_HINT =
  "HRLA (the paper's method: position and velocity, each step drawn exactly), ULA (underdamped: momentum, the position moved only by the velocity) and OLA (overdamped: no momentum, a downhill step plus a kick), from the same starts.";
