// The plan drawing worker: parses a plan's plan.json and paths.geojson (tens of MB for a 100 000-vertex
// path), builds its geometry (plan-geometry.ts) and draws map tiles on an OffscreenCanvas, so that the
// page's main thread neither parses nor rasterises the plan and pan and zoom stay smooth. Messages
// (plan-source.ts is the other end):
//   in:  {type: 'prepare', key, plan: ArrayBuffer, paths: ArrayBuffer}   → {type: 'prepared', key, plan, summary} | {type: 'error', key, message}
//        {type: 'tile', key, req, z, x, y, size, dpr}                    → {type: 'tile', req, bitmap | null}
//        {type: 'cancel', req}  {type: 'drop', key}
import { drawTile, parsePlan, type Geometry } from './plan-geometry.ts';

export type ToWorker =
  | { type: 'prepare'; key: number; plan: ArrayBuffer; paths: ArrayBuffer }
  | { type: 'tile'; key: number; req: number; z: number; x: number; y: number; size: number; dpr: number }
  | { type: 'cancel'; req: number }
  | { type: 'drop'; key: number };

const plans = new Map<number, Geometry>();
const queue: Extract<ToWorker, { type: 'tile' }>[] = [];
let canvas: OffscreenCanvas | null = null;
let scheduled = false;

const post = (msg: unknown, transfer: Transferable[] = []) => (self as unknown as Worker).postMessage(msg, transfer);

/** One tile per turn, so that cancel messages (tiles Leaflet no longer shows) are read in between. */
function next(): void {
  scheduled = false;
  const t = queue.shift();
  if (!t) return;
  const g = plans.get(t.key);
  let bitmap: ImageBitmap | null = null;
  if (g) {
    const px = Math.round(t.size * t.dpr);
    if (!canvas || canvas.width !== px) canvas = new OffscreenCanvas(px, px);
    const ctx = canvas.getContext('2d')!;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, px, px);
    if (drawTile(ctx, g, t.z, t.x, t.y, t.size, t.dpr) > 0) bitmap = canvas.transferToImageBitmap();
  }
  post({ type: 'tile', req: t.req, bitmap }, bitmap ? [bitmap] : []);
  schedule();
}

function schedule(): void {
  if (scheduled || !queue.length) return;
  scheduled = true;
  setTimeout(next, 0);
}

self.onmessage = (e: MessageEvent<ToWorker>) => {
  const m = e.data;
  if (m.type === 'prepare') {
    try {
      const { geometry, summary, plan } = parsePlan(m.plan, m.paths);
      plans.set(m.key, geometry);
      post({ type: 'prepared', key: m.key, plan, summary });
    } catch (err) {
      post({ type: 'error', key: m.key, message: `the plan's files cannot be read: ${(err as Error).message}` });
    }
  } else if (m.type === 'tile') {
    queue.push(m);
    schedule();
  } else if (m.type === 'cancel') {
    const i = queue.findIndex((t) => t.req === m.req);
    if (i >= 0) {
      queue.splice(i, 1);
      post({ type: 'tile', req: m.req, bitmap: null });
    }
  } else if (m.type === 'drop') {
    plans.delete(m.key);
  }
};
