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
