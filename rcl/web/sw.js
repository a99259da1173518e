// The service worker: after the first visit the site works offline (every
// file of the build cached, named in site.json), and each response gets
// the cross-origin isolation headers, so a host that cannot send them
// (GitHub Pages) still gives the page shared memory (Ctrl-C, Stop).
const PREFIX = "rcl-site-";

async function cacheSite() {
  const site = await (await fetch("./site.json", { cache: "no-store" })).json();
  const name = PREFIX + site.build;
  if (await caches.has(name + "-complete")) return;
  const cache = await caches.open(name);
  await cache.addAll(["./", "./site.json", "./sw.js", ...site.files.map((f) => "./" + f)]);
  await caches.open(name + "-complete");        // the marker: all of it is there
  for (const key of await caches.keys()) {
    if (key.startsWith(PREFIX) && !key.startsWith(name)) await caches.delete(key);
  }
}

self.addEventListener("install", (e) => { self.skipWaiting(); e.waitUntil(cacheSite().catch(() => {})); });
self.addEventListener("activate", (e) => e.waitUntil(self.clients.claim()));

function isolated(response) {
  if (!response || response.status === 0 || response.type === "opaque") return response;
  const headers = new Headers(response.headers);
  headers.set("Cross-Origin-Opener-Policy", "same-origin");
  headers.set("Cross-Origin-Embedder-Policy", "require-corp");
  headers.set("Cross-Origin-Resource-Policy", "same-origin");
  return new Response(response.body, { status: response.status, statusText: response.statusText, headers });
}

async function fromCache(request) {
  for (const key of await caches.keys()) {
    if (!key.startsWith(PREFIX) || key.endsWith("-complete")) continue;
    const hit = await (await caches.open(key)).match(request, { ignoreSearch: true });
    if (hit) return hit;
  }
  return null;
}

// The page and site.json from the network when it answers (a new build is
// seen at once, and cached again); the rest from the cache first.
async function respond(request) {
  const url = new URL(request.url);
  const fresh = request.mode === "navigate" || url.pathname.endsWith("/site.json");
  if (!fresh) {
    const hit = await fromCache(request);
    if (hit) return hit;
  }
  try {
    const response = await fetch(request);
    if (fresh && url.pathname.endsWith("/site.json")) cacheSite().catch(() => {});
    return response;
  } catch (e) {
    const hit = await fromCache(request);
    if (hit) return hit;
    throw e;
  }
}

self.addEventListener("fetch", (e) => {
  if (e.request.method !== "GET" || new URL(e.request.url).origin !== location.origin) return;
  e.respondWith(respond(e.request).then(isolated));
});
