// The settings as the page holds them: every control, its place in the
// address, and the checks and plain-words messages that go next to it.

import { parseView } from "./view.js";
import { parseChanges } from "./tune.js";

/** Every setting in the address, with its control and its kind. */
export const FIELDS = [
  { id: "potential", kind: "select", label: "landscape" },
  { id: "formula", kind: "text", label: "formula" },
  { id: "fcx", kind: "number", label: "box centre x₁" },
  { id: "fcy", kind: "number", label: "box centre x₂" },
  { id: "fhalf", kind: "number", label: "box half-width" },
  { id: "sampler", kind: "select", label: "method" },
  { id: "compare", kind: "flag", label: "compare HRLA, ULA, OLA" },
  { id: "descent", kind: "flag", label: "gradient descent with restarts beside" },
  { id: "h", kind: "number", label: "step h" },
  { id: "chains", kind: "number", label: "chains N" },
  { id: "spf", kind: "number", label: "steps per frame" },
  { id: "schedule", kind: "choice", values: ["constant", "linear"], label: "temperature schedule" },
  { id: "a", kind: "number", label: "a" },
  { id: "aLow", kind: "number", label: "a_low" },
  { id: "aHigh", kind: "number", label: "a_high" },
  { id: "K", kind: "number", label: "K" },
  { id: "cx", kind: "number", label: "centre c₁" },
  { id: "cy", kind: "number", label: "centre c₂" },
  { id: "spread", kind: "number", label: "spread s" },
  { id: "seed", kind: "seed", label: "seed" },
  { id: "stopSteps", kind: "number", optional: true, label: "stop after" },
  { id: "stopTarget", kind: "number", optional: true, label: "stop at U − U* ≤" },
  { id: "group", kind: "number", label: "group size n" },
  { id: "eps", kind: "number", label: "ε" },
  { id: "show", kind: "choice", values: ["u", "density"], label: "background" },
  { id: "play", kind: "choice", values: ["0", "1"], label: "play" },
  { id: "view", kind: "view", label: "view" },
  { id: "tune", kind: "tune", label: "changes of h and a during the run" },
];

export const FIELD = Object.fromEntries(FIELDS.map((f) => [f.id, f]));

/** The kernel's and the wrapper's names of settings, as the page's controls. */
const KERNEL_NAMES = {
  h: "h",
  "alpha h": "h",
  a: "a",
  a_low: "aLow",
  a_high: "aHigh",
  steps: "K",
  chains: "chains",
  std_dev: "spread",
  mean: "cx",
  centre: "cx",
  spread: "spread",
  seed: "seed",
  sampler: "sampler",
  potential: "potential",
  formula: "formula",
  box: "fhalf",
  stopSteps: "stopSteps",
  "step budget": "stopSteps",
  stopTarget: "stopTarget",
  target: "stopTarget",
};

/** The control a kernel error is about, from its `field` property. */
export function fieldOf(error) {
  return KERNEL_NAMES[error.field] ?? null;
}

/** A kernel or wrapper message in plain words: labels for names, no backticks. */
export function plain(message) {
  return message
    .replace(/`([^`]+)`/g, (_, name) => FIELD[KERNEL_NAMES[name]]?.label ?? name)
    .replace(/must be finite and > 0, got (\S+)/, "must be a number above 0 (got $1)")
    .replace(/must be finite and >= 0, got (\S+)/, "must be a number, 0 or more (got $1)")
    .replace(/must be finite, got (\S+)/, "must be a finite number (got $1)")
    .replace(/must be a whole number >= 0/, "must be a whole number, 0 or more")
    .replace(/, got (\S+)$/, " (got $1)");
}

/** A number typed in a field: NaN when empty or not a number. */
export function parseNumber(text) {
  const t = String(text).trim();
  return t === "" ? NaN : Number(t);
}

/**
 * Reads the address. Returns { values: {id: text}, problems: [{ id, text }] }:
 * every parameter that is not a setting, or whose value the setting cannot
 * take, is a problem (and is left out of values, so the control keeps its
 * default). `options(id)` lists a select's values.
 */
export function readAddress(search, options) {
  const q = new URLSearchParams(search);
  const values = {};
  const problems = [];
  for (const [key, value] of q) {
    const field = FIELD[key];
    if (!field) {
      problems.push({ id: null, text: `the address has “${key}=${value}”, which is not a setting of this page: ignored` });
      continue;
    }
    let bad = null;
    if (field.kind === "select" && !options(key).includes(value)) {
      bad = `must be one of ${options(key).join(", ")}`;
    } else if (field.kind === "choice" && !field.values.includes(value)) {
      bad = `must be one of ${field.values.join(", ")}`;
    } else if (field.kind === "flag" && !["0", "1"].includes(value)) {
      bad = "must be 0 or 1";
    } else if (field.kind === "number" && !(field.optional && value === "") && !Number.isFinite(parseNumber(value))) {
      bad = "is not a number";
    } else if (field.kind === "view" && !parseView(value)) {
      bad = "must be cx,cy,half with half above 0";
    } else if (field.kind === "tune" && parseChanges(value) === null) {
      bad = "must be changes k:h:a at increasing iterations k, separated by commas";
    } else if (field.kind === "seed" && !/^[0-9]+$/.test(value)) {
      bad = "must be a whole number between 0 and 2^64 − 1";
    }
    if (bad) problems.push({ id: key, text: `the address gave ${field.label} “${value}”, which ${bad}: the default is used` });
    else values[key] = value;
  }
  return { values, problems };
}
