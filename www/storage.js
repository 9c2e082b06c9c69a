// What the page keeps in this browser: the Bézier model, the Free-form scene, the script and the
// mode last used. localStorage can be missing or refuse (private modes, quota): the page works on
// without it, and `set` says whether the value was kept.

export const KEYS = {
  model: 'bezsolid.model.v1',
  freeform: 'bezsolid.freeform.v1',
  script: 'bezsolid.script.v1',
  hyperfun: 'bezsolid.hyperfun.v1',
  hyperfunBox: 'bezsolid.hyperfun-box.v1',
  workspace: 'bezsolid.workspace.v1',
  hinted: 'bezsolid.hinted.v1', // the first-visit hint was used or dismissed
};

export const storage = {
  get(key) {
    try { return localStorage.getItem(key); } catch { return null; }
  },
  set(key, value) {
    try { localStorage.setItem(key, value); return true; } catch { return false; }
  },
  remove(key) {
    try { localStorage.removeItem(key); } catch { /* nothing kept, nothing to remove */ }
  },
};
