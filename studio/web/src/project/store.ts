// Where projects are kept: the browser's IndexedDB, one record a project, each save a new
// revision. Each behaviour the browser can force on us is defined here (docs/studio.md,
// "Projects"):
// - no IndexedDB (private mode, storage off): the projects live in the page's memory, and
//   the page says to save a file;
// - the quota reached: the save fails, the last saved revision stays as it was, and the
//   page says so;
// - two tabs on one project: a tab saves only over the revision it opened; when the other
//   tab saved in between, this tab's work goes to a copy ("... (other tab)"), never over it.
// A record that cannot be read is reported by its id and name and left untouched.
import type { Project } from "./document";

export interface Stored { id: string; name: string; updated: number; rev: number; doc: unknown }

const DB = "articula";
const STORE = "projects";

export class ProjectStore {
  persistent = true; // false: memory only (no IndexedDB here)
  lastPutMs = 0; // the main thread's part of the last save: the browser copies the record as put() is called
  private db: IDBDatabase | null = null;
  private memory = new Map<string, Stored>();
  private channel: BroadcastChannel | null = null;
  /** Another tab saved project `id` at revision `rev`. */
  onOtherTab: (id: string, rev: number) => void = () => undefined;

  async open(): Promise<void> {
    try {
      if (typeof indexedDB === "undefined" || !indexedDB) throw new Error("no IndexedDB");
      this.db = await new Promise<IDBDatabase>((resolve, reject) => {
        const req = indexedDB.open(DB, 1);
        req.onupgradeneeded = () => req.result.createObjectStore(STORE, { keyPath: "id" });
        req.onsuccess = () => resolve(req.result);
        req.onerror = () => reject(req.error);
        req.onblocked = () => reject(new Error("blocked"));
      });
    } catch {
      this.db = null;
      this.persistent = false;
    }
    try {
      this.channel = new BroadcastChannel("articula-projects");
      this.channel.onmessage = (e) => this.onOtherTab(String(e.data?.id), Number(e.data?.rev));
    } catch {
      this.channel = null;
    }
  }

  private tx<T>(mode: IDBTransactionMode, work: (s: IDBObjectStore) => IDBRequest<T> | void): Promise<T | undefined> {
    return new Promise((resolve, reject) => {
      const t = this.db!.transaction(STORE, mode);
      let result: T | undefined;
      const req = work(t.objectStore(STORE));
      if (req) req.onsuccess = () => (result = req.result);
      t.oncomplete = () => resolve(result);
      t.onerror = () => reject(t.error ?? new Error("the browser's store failed"));
      t.onabort = () => reject(t.error ?? new Error("the browser's store refused the save"));
    });
  }

  async list(): Promise<Stored[]> {
    const all = this.db ? ((await this.tx<Stored[]>("readonly", (s) => s.getAll())) ?? []) : [...this.memory.values()];
    return all.sort((a, b) => b.updated - a.updated);
  }

  async get(id: string): Promise<Stored | undefined> {
    return this.db ? this.tx<Stored>("readonly", (s) => s.get(id)) : this.memory.get(id);
  }

  /** Saves `doc` as project `id` over revision `baseRev`: the revision saved and the id it
   * went to (another id when another tab saved `id` after `baseRev`: a copy). */
  async save(id: string, baseRev: number, doc: Project): Promise<{ id: string; rev: number; forked: boolean }> {
    const now = Date.now();
    if (!this.db) {
      const cur = this.memory.get(id);
      const rev = (cur?.rev ?? 0) + 1;
      this.memory.set(id, { id, name: doc.name, updated: now, rev, doc: structuredClone(doc) });
      return { id, rev, forked: false };
    }
    const cur = await this.get(id);
    if (cur && cur.rev !== baseRev) {
      const copy = newId();
      const named = { ...doc, name: `${doc.name} (other tab)` };
      await this.tx("readwrite", (s) => s.put({ id: copy, name: named.name, updated: now, rev: 1, doc: named }));
      this.announce(copy, 1);
      return { id: copy, rev: 1, forked: true };
    }
    const rev = (cur?.rev ?? 0) + 1;
    await this.tx("readwrite", (s) => {
      const t0 = performance.now();
      const req = s.put({ id, name: doc.name, updated: now, rev, doc });
      this.lastPutMs = performance.now() - t0;
      return req;
    });
    this.announce(id, rev);
    return { id, rev, forked: false };
  }

  /** Puts a record back as it was (undo of a delete). */
  async restore(rec: Stored): Promise<void> {
    if (!this.db) this.memory.set(rec.id, rec);
    else await this.tx("readwrite", (s) => s.put(rec));
  }

  async remove(id: string): Promise<void> {
    if (!this.db) this.memory.delete(id);
    else await this.tx("readwrite", (s) => s.delete(id));
    this.announce(id, -1);
  }

  private announce(id: string, rev: number): void {
    this.channel?.postMessage({ id, rev });
  }
}

export function newId(): string {
  return `p-${Date.now().toString(36)}-${Math.random().toString(36).slice(2, 8)}`;
}
