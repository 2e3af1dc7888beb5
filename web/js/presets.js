// The guided path's links (in the page's header) are plain addresses the
// page reads; two of them also name a place with a fragment, which no
// setting can express: `#step` lays one step bare as soon as the run is
// ready (as the Step button does), `#ddim` brings the d-dimensional view
// on screen. The page rewrites its address as it runs, dropping the
// fragment, so it is read once, when this module loads, and on a later
// change of the fragment alone (a link to the page's own address).

const $ = (id) => document.getElementById(id);

/** The fragment the page was opened with. */
const opened = typeof location === "undefined" ? "" : location.hash;

function act(hash) {
  if (hash === "#step") {
    $("step").click();
    $("step").scrollIntoView({ block: "nearest" });
  } else if (hash === "#ddim") {
    $("ddim").scrollIntoView({ block: "start" });
  }
}

/** Acts on the fragment the page was opened with; call once the runs are ready. */
export function setUpPresets() {
  act(opened);
  window.addEventListener("hashchange", () => act(location.hash));
}
