// What the page needs of its browser, checked before anything else runs (main.ts imports this
// module first). A page must not die on its environment:
// - a locale that is no language tag: WebKitGTK reports navigator.language "C" when LANG is
//   C.UTF-8 or unset, and `new Intl.NumberFormat("C")` throws a RangeError (uPlot makes one as
//   it loads). The page then reads the nearest valid tag, or "en";
// - no storage (private browsing, or storage turned off): `storage` is null, and what the page
//   would keep lasts as long as the page;
// - no WebGL: `webgl` is false, and the view says so while every panel still works.

function validLanguage(tag: unknown): string {
  if (typeof tag !== "string" || tag === "") return "en";
  try {
    return Intl.getCanonicalLocales(tag)[0] ?? "en";
  } catch {
    // "C", "C.UTF-8", "en_US.UTF-8", "POSIX": a language before a dot or underscore, if any
    const lang = tag.split(/[._@]/)[0];
    try {
      return lang && lang !== "C" && lang !== "POSIX" ? (Intl.getCanonicalLocales(lang)[0] ?? "en") : "en";
    } catch {
      return "en";
    }
  }
}

/** The page's language: a valid BCP 47 tag, whatever the browser says. */
export const language = validLanguage(navigator.language);
if (language !== navigator.language) {
  // libraries read navigator.language themselves (uPlot): they see the valid tag
  try {
    Object.defineProperty(navigator, "language", { get: () => language, configurable: true });
  } catch {
    /* nothing more to do: our own code uses `language` */
  }
}

/** localStorage, or null where the browser has none for this page. */
export const storage: Storage | null = (() => {
  try {
    const s = window.localStorage;
    const key = "articula.storage-check";
    s.setItem(key, "1");
    s.removeItem(key);
    return s;
  } catch {
    return null;
  }
})();

/** Reads a stored string; null when there is none or no storage. */
export function stored(key: string): string | null {
  try {
    return storage?.getItem(key) ?? null;
  } catch {
    return null;
  }
}

/** Keeps a string; false when it cannot (no storage, or full). */
export function store(key: string, value: string): boolean {
  try {
    if (!storage) return false;
    storage.setItem(key, value);
    return true;
  } catch {
    return false;
  }
}
