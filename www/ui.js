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

/** A value as the panel shows it: three decimals, 0 for what rounds to it, powers of ten for the large. */
export const fmt = (v) => (Math.abs(v) < 5e-4 ? '0' : Math.abs(v) >= 1e4 ? v.toExponential(2) : v.toFixed(3));

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

/**
 * Marks the menu items that `selector` finds as usable (`on`) or not: a disabled item stays in
 * sight, greyed, and is passed over by the keys and by clicks.
 */
export function enableItems(selector, on) {
  for (const item of document.querySelectorAll(selector)) {
    if (on) item.removeAttribute('aria-disabled');
    else item.setAttribute('aria-disabled', 'true');
  }
}

/**
 * Wires a menu button (the WAI-ARIA menu button pattern): `button` (with `aria-controls` naming
 * its `role="menu"` list of `role="menuitem"` items, each with a `data-value`) opens the menu on a
 * click, Enter, Space or ↓ (↑: at the last item); in the menu ↑ ↓ Home End move, Enter, Space or
 * a click picks (`onPick(value)`), Esc closes it back to the button, Tab and a click elsewhere
 * close it. Nothing is done until an item is picked: moving through the items only moves.
 */
export function setupMenu(button, onPick) {
  const menu = $(button.getAttribute('aria-controls'));
  const items = () => [...menu.querySelectorAll('[role="menuitem"]')]
    .filter((item) => !item.hidden && item.getAttribute('aria-disabled') !== 'true');
  const isOpen = () => !menu.hidden;
  const focusItem = (item) => {
    for (const other of menu.querySelectorAll('[role="menuitem"]')) other.tabIndex = -1;
    if (!item) return;
    item.tabIndex = 0;
    item.focus();
  };
  const open = (at = 'first') => {
    menu.hidden = false;
    button.setAttribute('aria-expanded', 'true');
    const usable = items();
    focusItem(at === 'last' ? usable[usable.length - 1] : usable[0]);
  };
  const close = (refocus) => {
    if (!isOpen()) return;
    menu.hidden = true;
    button.setAttribute('aria-expanded', 'false');
    if (refocus) button.focus();
  };
  const pick = (item) => {
    if (!item || item.getAttribute('aria-disabled') === 'true') return;
    close(true);
    onPick(item.dataset.value);
  };
  button.addEventListener('click', () => (isOpen() ? close(true) : open()));
  button.addEventListener('keydown', (e) => {
    if (e.key === 'ArrowDown' || e.key === 'ArrowUp') {
      e.preventDefault();
      open(e.key === 'ArrowUp' ? 'last' : 'first');
    } else if (e.key === 'Escape' && isOpen()) {
      e.preventDefault();
      close(true);
    }
  });
  menu.addEventListener('click', (e) => pick(e.target.closest('[role="menuitem"]')));
  menu.addEventListener('keydown', (e) => {
    const usable = items();
    const k = usable.indexOf(document.activeElement);
    const go = {
      ArrowDown: () => focusItem(usable[(k + 1) % usable.length]),
      ArrowUp: () => focusItem(usable[(k - 1 + usable.length) % usable.length]),
      Home: () => focusItem(usable[0]),
      End: () => focusItem(usable[usable.length - 1]),
      Enter: () => pick(document.activeElement),
      ' ': () => pick(document.activeElement),
      Escape: () => close(true),
    }[e.key];
    if (go) {
      e.preventDefault();
      go();
    } else if (e.key === 'Tab') {
      close(true); // focus goes on from the button
    }
  });
  document.addEventListener('pointerdown', (e) => {
    if (isOpen() && !menu.contains(e.target) && !button.contains(e.target)) close(false);
  });
  return { close };
}

/** Clears the measurement shown in output `id` once the model is no longer the `revision` it was
 * made of. */
export function forgetStale(id, revision) {
  const out = $(id);
  if (out?.dataset.revision !== undefined && out.dataset.revision !== String(revision)) {
    out.textContent = '';
    delete out.dataset.revision;
  }
}
