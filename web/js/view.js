// The view of the landscape as a visitor moves it: a square { cx, cy, half }
// zoomed about a point (the wheel's cursor, a pinch's centre, or the centre
// for the buttons and keys), panned by a drag (mouse, pen, a sideways swipe or two fingers) or
// the arrow keys, kept within a range of the landscape's own view, and
// written in the address as "cx,cy,half".

/** Zoom range relative to the landscape's own view. */
const MIN_HALF = 1e-3;
const MAX_HALF = 50;

/** `view` zoomed by `factor` (> 1 zooms in) about the point [x, y], which stays where it is on the screen. */
export function zoomAbout(view, [x, y], factor, home) {
  const half = clampHalf(view.half / factor, home);
  const kept = half / view.half;
  return { cx: x + (view.cx - x) * kept, cy: y + (view.cy - y) * kept, half };
}

/** `view` moved so that the landscape shifts by [dx, dy] in its own units. */
export function pan(view, [dx, dy]) {
  return { cx: view.cx - dx, cy: view.cy - dy, half: view.half };
}

/** What an arrow key pans, as a share of the view's width. */
const KEY_PAN = 0.1;
/** What + and − zoom by, as the buttons do. */
export const ZOOM_STEP = 1.5;

/**
 * The view after a key pressed on the picture: the arrows pan (the view
 * moves the arrow's way), + and − zoom about the centre, 0 goes home;
 * null for any other key.
 */
export function keyView(view, key, home) {
  const d = 2 * view.half * KEY_PAN;
  const centre = [view.cx, view.cy];
  switch (key) {
    case "ArrowLeft":
      return pan(view, [d, 0]);
    case "ArrowRight":
      return pan(view, [-d, 0]);
    case "ArrowUp":
      return pan(view, [0, -d]);
    case "ArrowDown":
      return pan(view, [0, d]);
    case "+":
    case "=":
      return zoomAbout(view, centre, ZOOM_STEP, home);
    case "-":
    case "_":
      return zoomAbout(view, centre, 1 / ZOOM_STEP, home);
    case "0":
    case "Home":
      return { ...home };
    default:
      return null;
  }
}

function clampHalf(half, home) {
  return Math.min(home.half * MAX_HALF, Math.max(home.half * MIN_HALF, half));
}

/** Whether two views are the same. */
export function sameView(a, b) {
  return a.cx === b.cx && a.cy === b.cy && a.half === b.half;
}

/** The address's form of a view, with round numbers (12 significant digits). */
export function formatView(v) {
  return [v.cx, v.cy, v.half].map((t) => String(+t.toPrecision(12))).join(",");
}

/** A view from the address's "cx,cy,half", or null when it is not one. */
export function parseView(text) {
  const parts = String(text).split(",");
  if (parts.length !== 3 || parts.some((p) => p.trim() === "")) return null;
  const [cx, cy, half] = parts.map(Number);
  return [cx, cy, half].every(Number.isFinite) && half > 0 ? { cx, cy, half } : null;
}
