// Articula Studio's service worker: the whole site is kept on install, so the studio opens
// and works with no network once it has been loaded (a classroom with a poor network; an
// installed app). Network first, so a new version is seen as soon as the server is reached;
// the kept copy answers when it is not. build.mjs fills in the version and the file list.
const VERSION = "__VERSION__";
const FILES = __FILES__;
const CACHE = `articula-studio-${VERSION}`;

self.addEventListener("install", (e) => {
  e.waitUntil(caches.open(CACHE).then((c) => c.addAll(FILES)).then(() => self.skipWaiting()));
});

self.addEventListener("activate", (e) => {
  e.waitUntil(caches.keys()
    .then((keys) => Promise.all(keys.filter((k) => k.startsWith("articula-studio-") && k !== CACHE).map((k) => caches.delete(k))))
    .then(() => self.clients.claim()));
});

self.addEventListener("fetch", (e) => {
  const url = new URL(e.request.url);
  if (e.request.method !== "GET" || url.origin !== location.origin || url.pathname.endsWith("/ws")) return;
  e.respondWith(fetch(e.request).then((r) => {
    if (r.ok && !url.search) {
      const copy = r.clone();
      caches.open(CACHE).then((c) => c.put(e.request, copy));
    }
    return r;
  }).catch(() => caches.match(e.request, { ignoreSearch: true }).then((r) => r ?? Response.error())));
});
