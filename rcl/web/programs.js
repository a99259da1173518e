// The user's files, kept in the browser between visits (IndexedDB), and
// programs carried in a link (deflate, then base64url, in the fragment).

const DB = "rcl", STORE = "files";

function open() {
  return new Promise((resolve, reject) => {
    const req = indexedDB.open(DB, 1);
    req.onupgradeneeded = () => req.result.createObjectStore(STORE);
    req.onsuccess = () => resolve(req.result);
    req.onerror = () => reject(req.error);
  });
}

async function tx(mode, work) {
  const db = await open();
  return new Promise((resolve, reject) => {
    const t = db.transaction(STORE, mode);
    const result = work(t.objectStore(STORE));
    t.oncomplete = () => resolve(result.result);
    t.onerror = () => reject(t.error);
  });
}

export class Files {
  // -> {name: text}
  async all() {
    const db = await open();
    return new Promise((resolve, reject) => {
      const out = {};
      const req = db.transaction(STORE).objectStore(STORE).openCursor();
      req.onsuccess = () => {
        const c = req.result;
        if (c) { out[c.key] = c.value; c.continue(); } else resolve(out);
      };
      req.onerror = () => reject(req.error);
    });
  }
  put(name, text) { return tx("readwrite", (s) => s.put(text, name)); }
  remove(name) { return tx("readwrite", (s) => s.delete(name)); }
}

// A file name INCLUDE can take: no folders, no blanks.
export function cleanName(name) {
  const base = name.split(/[\\/]/).pop().replace(/\s+/g, "-");
  return base || "program.fs";
}

// ------------------------------------------------------------ share links
function toBase64url(bytes) {
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function fromBase64url(text) {
  const s = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

async function pipe(bytes, stream) {
  const out = new Response(new Blob([bytes]).stream().pipeThrough(stream));
  return new Uint8Array(await out.arrayBuffer());
}

export async function encodeProgram(text) {
  return toBase64url(await pipe(new TextEncoder().encode(text), new CompressionStream("deflate")));
}

export async function decodeProgram(code) {
  return new TextDecoder().decode(await pipe(fromBase64url(code), new DecompressionStream("deflate")));
}

// The page's options from its fragment: #p=PROGRAM&name=NAME&embed
export function fragmentOptions() {
  const out = {};
  for (const part of location.hash.replace(/^#/, "").split("&")) {
    if (!part) continue;
    const i = part.indexOf("=");
    out[i < 0 ? part : part.slice(0, i)] = i < 0 ? true : decodeURIComponent(part.slice(i + 1));
  }
  return out;
}
