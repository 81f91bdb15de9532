// Loads a plan for drawing and draws its tiles: in the plan worker (plan-worker.ts) when the browser
// has module workers and OffscreenCanvas, else in the page with the same code (plan-geometry.ts),
// one tile per task.
import { api, ApiError } from './api.ts';
import { drawTile, parsePlan, type Geometry, type PlanJson, type PlanSummary } from './plan-geometry.ts';
import type { ToWorker } from './plan-worker.ts';

/** A plan ready to draw: plan.json without its regions (those stay with the drawing code), and what drawPlan needs. */
export interface PreparedPlan {
  key: number;
  plan: PlanJson;
  summary: PlanSummary;
}

interface Backend {
  prepare(key: number, plan: ArrayBuffer, paths: ArrayBuffer): Promise<Omit<PreparedPlan, 'key'>>;
  /** Draws tile (z, x, y) into `target`; resolves when done (or cancelled). */
  tile(key: number, z: number, x: number, y: number, size: number, dpr: number, target: HTMLCanvasElement): { done: Promise<void>; cancel(): void };
  drop(key: number): void;
}

type FromWorker =
  | { type: 'prepared'; key: number; plan: PlanJson; summary: PlanSummary }
  | { type: 'error'; key: number; message: string }
  | { type: 'tile'; req: number; bitmap: ImageBitmap | null };

class WorkerBackend implements Backend {
  private worker = new Worker(new URL('./plan-worker.ts', import.meta.url), { type: 'module' });
  private prepares = new Map<number, { ok: (p: Omit<PreparedPlan, 'key'>) => void; fail: (e: Error) => void }>();
  private tiles = new Map<number, (b: ImageBitmap | null) => void>();
  private req = 0;

  constructor() {
    this.worker.onmessage = (e: MessageEvent<FromWorker>) => {
      const m = e.data;
      if (m.type === 'tile') {
        const f = this.tiles.get(m.req);
        this.tiles.delete(m.req);
        if (f) f(m.bitmap);
        else m.bitmap?.close();
        return;
      }
      const p = this.prepares.get(m.key);
      this.prepares.delete(m.key);
      if (m.type === 'prepared') p?.ok({ plan: m.plan, summary: m.summary });
      else p?.fail(new ApiError(0, '', m.message));
    };
    this.worker.onerror = (e) => {
      for (const p of this.prepares.values()) p.fail(new ApiError(0, '', `the plan drawing worker failed: ${e.message}`));
      this.prepares.clear();
    };
  }
  private send(m: ToWorker, transfer: Transferable[] = []) {
    this.worker.postMessage(m, transfer);
  }
  prepare(key: number, plan: ArrayBuffer, paths: ArrayBuffer) {
    return new Promise<Omit<PreparedPlan, 'key'>>((ok, fail) => {
      this.prepares.set(key, { ok, fail });
      this.send({ type: 'prepare', key, plan, paths }, [plan, paths]);
    });
  }
  tile(key: number, z: number, x: number, y: number, size: number, dpr: number, target: HTMLCanvasElement) {
    const req = ++this.req;
    const done = new Promise<void>((ok) => {
      this.tiles.set(req, (bitmap) => {
        // handed over without a copy (no canvas work on the page's thread)
        if (bitmap) target.getContext('bitmaprenderer')?.transferFromImageBitmap(bitmap);
        ok();
      });
    });
    this.send({ type: 'tile', key, req, z, x, y, size, dpr });
    return { done, cancel: () => this.send({ type: 'cancel', req }) };
  }
  drop(key: number) {
    this.send({ type: 'drop', key });
  }
}

class PageBackend implements Backend {
  private plans = new Map<number, Geometry>();
  async prepare(key: number, planBytes: ArrayBuffer, pathsBytes: ArrayBuffer) {
    const { geometry, summary, plan } = parsePlan(planBytes, pathsBytes);
    this.plans.set(key, geometry);
    return { plan, summary };
  }
  tile(key: number, z: number, x: number, y: number, size: number, dpr: number, target: HTMLCanvasElement) {
    let timer = 0;
    const done = new Promise<void>((ok) => {
      timer = window.setTimeout(() => {
        const g = this.plans.get(key);
        const ctx = target.getContext('2d');
        if (g && ctx) drawTile(ctx, g, z, x, y, size, dpr);
        ok();
      }, 0);
    });
    return { done, cancel: () => window.clearTimeout(timer) };
  }
  drop(key: number) {
    this.plans.delete(key);
  }
}

let backend: Backend | null = null;
function getBackend(): Backend {
  if (!backend) {
    try {
      backend = typeof Worker !== 'undefined' && typeof OffscreenCanvas !== 'undefined' ? new WorkerBackend() : new PageBackend();
    } catch {
      backend = new PageBackend();
    }
  }
  return backend;
}

let keys = 0;

/** Fetches plan `planId`'s plan.json and paths.geojson and prepares them for drawing. */
export async function loadPlan(planId: number): Promise<PreparedPlan> {
  const [plan, paths] = await Promise.all([api.bytes(`/plans/${planId}/plan.json`), api.bytes(`/plans/${planId}/paths.geojson`)]);
  const key = ++keys;
  return { key, ...(await getBackend().prepare(key, plan, paths)) };
}

export const drawPlanTile: Backend['tile'] = (...a) => getBackend().tile(...a);

/** Frees what the drawing code holds for a plan. */
export function dropPlan(p: PreparedPlan): void {
  getBackend().drop(p.key);
}
