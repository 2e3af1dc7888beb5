// The per-frame time budget: a frame advances the run in growing chunks
// and stops asking for more once its time is spent, so that no setting of
// steps per frame can freeze the tab (the browser gets the thread back
// within about one budget). The clock is a parameter, so the rule can be
// checked with a clock that does not depend on the machine's speed.

/** Milliseconds of stepping per frame: leaves room for drawing at 60 frames/s. */
export const FRAME_BUDGET_MS = 10;

/**
 * Runs `advance(k)` for a total of at most `wanted` steps, in chunks of
 * 1, 2, 4, ... steps, until `wanted` are done or `budgetMs` has passed on
 * `now()`. A chunk that the cost measured so far says would overrun the
 * budget is shrunk to fit (one step at least), so a frame lasts at most
 * the budget plus one step's worth. `advance` returns false to stop early
 * (the run ended). Returns { done, capped }.
 */
export function stepWithin(wanted, advance, now, budgetMs = FRAME_BUDGET_MS) {
  const start = now();
  let done = 0;
  let chunk = 1;
  while (done < wanted) {
    const elapsed = now() - start;
    if (done > 0 && elapsed >= budgetMs) break;
    if (done > 0 && elapsed > 0) {
      const perStep = elapsed / done;
      chunk = Math.max(1, Math.min(chunk, Math.floor((budgetMs - elapsed) / perStep)));
    }
    const k = Math.min(chunk, wanted - done);
    const going = advance(k);
    done += k;
    if (going === false) break;
    chunk *= 2;
  }
  return { done, capped: done < wanted };
}

/** A frame slower than this (ms since the last) asks for less drawing; 60 frames/s is 16.7. */
export const SLOW_FRAME_MS = 21;
/** A frame at most this slow lets the drawing grow back. */
export const FAST_FRAME_MS = 18;

/**
 * The drawing's budget, in trail segments per frame. Canvas drawing is
 * recorded when called and rasterised later, so a clock around the calls
 * would not see its cost; the time from one frame to the next does. A
 * slow frame halves the cap (down to `min`), a fast one grows it by a
 * tenth (up to `max`), so the trails shorten exactly as much as this
 * machine needs to keep its frame rate, and grow back when it can. The
 * chains' dots are never cut: positions are always all drawn.
 */
export class DrawBudget {
  constructor(now, { min = 2048, max = 1 << 20, start = 8192 } = {}) {
    this.now = now;
    this.min = min;
    this.max = max;
    this.cap = start;
    this.last = null;
  }

  /** Called once per frame, before drawing: adapts the cap to the last frame's length; returns it. */
  frame() {
    const t = this.now();
    if (this.last !== null) {
      const dt = t - this.last;
      if (dt > SLOW_FRAME_MS) this.cap = Math.max(this.min, Math.floor(this.cap / 2));
      else if (dt <= FAST_FRAME_MS) this.cap = Math.min(this.max, Math.ceil(this.cap * 1.1));
    }
    this.last = t;
    return this.cap;
  }
}

/**
 * How many trail segments back (ages) each chain's trail is drawn with at
 * most `cap` segments in all over `chains` chains, of the `available` ages
 * kept: the newest first, at least one when any is kept.
 */
export function trailAges(available, chains, cap) {
  if (available <= 0 || chains <= 0) return 0;
  return Math.max(1, Math.min(available, Math.floor(cap / chains)));
}
