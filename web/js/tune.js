// Changing the step h and the inverse temperature a of a running run: the
// chains take the new values from where they are (the kernel keeps every
// chain's state and random stream), and each change is recorded with the
// iteration it was made at. The address carries the record, and a replay
// applies each change at the same iteration, however the frames cut the
// stepping: the run's numbers depend on when it changed, bit for bit.

/** The sliders' scales: log10 of the value, and the range each covers. */
export const SLIDERS = {
  h: { slider: "h-slider", min: -4, max: 0 },
  a: { slider: "a-slider", min: -2, max: 3 },
};

/** A slider's value (log10) as a round number of 3 significant digits. */
export function fromSlider(position) {
  return +(10 ** Number(position)).toPrecision(3);
}

/** Where a value sits on its slider (clamped to the slider's range by the browser). */
export function toSlider(value) {
  return value > 0 && Number.isFinite(value) ? String(Math.log10(value)) : null;
}

/** The address's form of the record: "k:h:a" per change, in order. */
export function formatChanges(changes) {
  return changes.map((c) => `${c.k}:${c.h}:${c.a ?? ""}`).join(",");
}

/**
 * The record from the address: [{ k, h, a }] with k whole, above 0 and
 * increasing, h and a numbers (a empty under annealing, where the schedule
 * sets it); null when the text is not one.
 */
export function parseChanges(text) {
  if (text === "") return [];
  const changes = [];
  for (const part of String(text).split(",")) {
    const m = /^([0-9]+):([^:]+):([^:]*)$/.exec(part);
    if (!m) return null;
    const k = Number(m[1]);
    const h = Number(m[2]);
    const a = m[3] === "" ? null : Number(m[3]);
    if (!(Number.isSafeInteger(k) && k > 0) || !Number.isFinite(h) || (a !== null && !Number.isFinite(a))) return null;
    if (changes.length && k <= changes[changes.length - 1].k) return null;
    changes.push({ k, h, a });
  }
  return changes;
}

/**
 * Records a change made at iteration `k`: changes recorded after `k` (a
 * replay not yet there) are the visitor's no longer, and a second change
 * at the same iteration replaces the first. Returns the new record.
 */
export function record(changes, change) {
  const kept = changes.filter((c) => c.k < change.k);
  kept.push(change);
  return kept;
}

/**
 * Advances `run` by `steps`, applying each change of `changes` at its
 * iteration (before the step that leaves it); `run.applied` counts the
 * changes it has taken. `retune(run, change)` applies one.
 */
export function advanceWithChanges(run, steps, changes, retune) {
  let left = steps;
  for (;;) {
    // A change before the run's start or already passed is not this run's.
    while (changes[run.applied] && changes[run.applied].k < run.iteration) run.applied++;
    while (changes[run.applied]?.k === run.iteration) retune(run, changes[run.applied++]);
    if (left <= 0 || !run.live) return;
    const next = changes[run.applied];
    const k = next ? Math.min(left, next.k - run.iteration) : left;
    const before = run.iteration;
    run.advance(k);
    left -= k;
    // A stopping rule ended the run within the chunk.
    if (run.iteration - before < k) return;
  }
}
