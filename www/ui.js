// What every part of the page uses: elements by id, the status line, numbers as the panel shows
// them, and files handed to the user.

export const $ = (id) => document.getElementById(id);

/** Says `message` on the status line; `kind` is 'info', 'warn' or 'error'. */
export function say(message, kind = 'info') {
  const line = $('status');
  line.textContent = message;
  line.dataset.kind = kind;
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
