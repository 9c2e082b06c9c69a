// What every part of the page uses: elements by id, the status line, numbers as the panel shows
// them, and files handed to the user.

export const $ = (id) => document.getElementById(id);

// How long a message that reports success stays in sight; errors and warnings stay until dismissed
// or replaced.
const INFO_MS = 5000;
let fade = 0;

/**
 * Says `message` in the status bar over the views; `kind` is 'info' (fades after a while), 'warn'
 * or 'error' (stay until dismissed or replaced).
 */
export function say(message, kind = 'info') {
  const bar = $('status-bar');
  const line = $('status');
  line.textContent = message;
  line.dataset.kind = kind;
  bar.dataset.kind = kind;
  bar.hidden = !message;
  clearTimeout(fade);
  if (kind === 'info') fade = setTimeout(() => { bar.hidden = true; }, INFO_MS);
}

/**
 * Wires the buttons that open a file picker (`data-picks` names the hidden file input): real
 * buttons, in the tab order and the accessibility tree, unlike a label around a hidden input.
 */
export function setupPickers() {
  for (const button of document.querySelectorAll('[data-picks]')) {
    button.addEventListener('click', () => $(button.dataset.picks).click());
  }
}

/** Wires the status bar's dismiss button (once, at start-up). */
export function setupStatus() {
  $('status-close').addEventListener('click', () => {
    clearTimeout(fade);
    $('status-bar').hidden = true;
  });
}

/** An error's message (a JsError, an Error, or whatever was thrown). */
export const messageOf = (err) => err?.message ?? String(err);

/** A value as the panel shows it: three decimals, and 0 for what rounds to it. */
export const fmt = (v) => (Math.abs(v) < 5e-4 ? '0' : v.toFixed(3));

/** Hands `blob` to the user as the file `name`. */
export function download(name, blob) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
  say(`Saved ${name}.`);
}

/**
 * Saves what `canvas` shows as the PNG `name`. Call it in the task that drew the frame: the browser
 * clears a WebGPU or WebGL canvas after the frame is shown.
 */
export function capture(canvas, name) {
  canvas.toBlob((blob) => {
    if (blob) download(name, blob);
    else say('The view could not be captured as PNG.', 'error');
  }, 'image/png');
}
