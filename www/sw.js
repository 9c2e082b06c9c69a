// The page's service worker: after one visit the modeler opens with no network. On install it
// keeps every file the page may need (pkg/offline.json, written by the web build: the page, its
// scripts and styles, the glue and each wasm module under its content-hashed name). While online
// everything is fetched as before and the copy kept is refreshed; a file under a content-hashed
// name never changes, so it is taken from the copy when there is one; offline, the copy answers.
// A classic worker (not a module): every browser that has service workers runs it.
const CACHE = 'bezsolid-offline-v1';
// `name.0123456789abcdef.wasm`: a file that never changes (see the xtask's assets.rs).
const HASHED = /\.[0-9a-f]{16}\.[a-z0-9]+$/;

const offlineList = async () => {
  const response = await fetch('./pkg/offline.json', { cache: 'no-cache' });
  if (!response.ok) throw new Error(`pkg/offline.json: ${response.status}`);
  return (await response.json()).files.map((f) => new URL(f, self.registration.scope).href);
};

self.addEventListener('install', (event) => {
  event.waitUntil((async () => {
    const cache = await caches.open(CACHE);
    await cache.addAll(await offlineList());
    await self.skipWaiting();
  })());
});

self.addEventListener('activate', (event) => {
  event.waitUntil((async () => {
    // Older caches, and copies of modules no longer named (a newer build's names replace them).
    for (const name of await caches.keys()) if (name !== CACHE) await caches.delete(name);
    try {
      const wanted = new Set(await offlineList());
      const cache = await caches.open(CACHE);
      for (const request of await cache.keys()) {
        if (HASHED.test(new URL(request.url).pathname) && !wanted.has(request.url)) await cache.delete(request);
      }
    } catch {
      // Offline while activating: nothing is pruned this time.
    }
    await self.clients.claim();
  })());
});

self.addEventListener('fetch', (event) => {
  const { request } = event;
  const url = new URL(request.url);
  if (request.method !== 'GET' || url.origin !== self.location.origin) return;
  event.respondWith((async () => {
    const cache = await caches.open(CACHE);
    // The page is one document whatever its query (?backend=…) or fragment (a link's model).
    const key = request.mode === 'navigate' ? new URL('./', self.registration.scope).href : request;
    if (HASHED.test(url.pathname)) {
      const kept = await cache.match(key);
      if (kept) return kept;
    }
    try {
      const response = await fetch(request);
      if (response.ok && response.type === 'basic') await cache.put(key, response.clone());
      return response;
    } catch (err) {
      const kept = await cache.match(key, { ignoreSearch: true });
      if (kept) return kept;
      throw err;
    }
  })());
});
