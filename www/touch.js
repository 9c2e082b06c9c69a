// The pointers down on one canvas, by pointerId, and what two of them do: a pinch step (their
// midpoint before, the ratio of their spread now to before, their midpoint's move). The views turn
// a step into a zoom and a pan (Rust: View2::pinch, Camera::pinch); this only measures.

/** A tracker of the pointers down on a canvas. */
export function pointers() {
  // Insertion order: the first two down lead a pinch; a third finger is ignored.
  const down = new Map();
  const firstTwo = () => [...down.values()].slice(0, 2);
  return {
    /** Pointer `id` went down at `[x, y]`; returns how many are down. */
    add(id, xy) {
      down.set(id, xy);
      return down.size;
    },
    /** Whether pointer `id` is down. */
    has: (id) => down.has(id),
    /** Pointer `id` went up or was cancelled; returns how many are still down. */
    remove(id) {
      down.delete(id);
      return down.size;
    },
    /** How many pointers are down. */
    count: () => down.size,
    /**
     * Pointer `id` moved to `[x, y]`. When it is one of the first two of two or more down, returns
     * the pinch step `{ x, y, scale, dx, dy }`: (x, y) their midpoint before, scale their spread
     * now over before (1 when they were on one spot), (dx, dy) the midpoint's move; else null.
     */
    move(id, xy) {
      if (!down.has(id)) return null;
      const before = firstTwo();
      const leading = [...down.keys()].slice(0, 2).includes(id);
      down.set(id, xy);
      if (before.length < 2 || !leading) return null;
      const after = firstTwo();
      const mid = ([a, b]) => [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
      const spread = ([a, b]) => Math.hypot(a[0] - b[0], a[1] - b[1]);
      const [m0, m1] = [mid(before), mid(after)];
      const [s0, s1] = [spread(before), spread(after)];
      const scale = s0 > 1 && s1 > 1 ? s1 / s0 : 1;
      return { x: m0[0], y: m0[1], scale, dx: m1[0] - m0[0], dy: m1[1] - m0[1] };
    },
    /** Forgets every pointer. */
    clear: () => down.clear(),
  };
}
