// Live job updates: one WebSocket to /api/v1/events shared by every watcher, reconnecting with a
// growing delay; while the socket is not open, each watched job is polled every 500 ms instead. A job
// is also read once after each (re)subscription, so a change made before it is never missed.
import { api, ApiError } from './api.ts';

export type JobState = 'queued' | 'running' | 'done' | 'failed' | 'cancelled';

export interface Job {
  id: number;
  kind: 'plan' | 'study' | 'comparison';
  mission_id: number;
  revision: number;
  state: JobState;
  progress: number;
  stage: string;
  cancel_requested: boolean;
  params: Record<string, unknown>;
  result: Record<string, unknown>;
  warnings: string[];
  metrics: Record<string, number>;
  error: { field?: string; message?: string } | null;
  artifacts?: { name: string; media_type: string; size: number; url: string | null }[];
}

export const terminal = (s: JobState): boolean => s === 'done' || s === 'failed' || s === 'cancelled';

/** The REST collection of a job kind: plans, studies, comparisons. */
export const collection = (kind: Job['kind']): string =>
  kind === 'plan' ? 'plans' : kind === 'study' ? 'studies' : 'comparisons';

interface Watch {
  id: number;
  kind: Job['kind'];
  onUpdate: (job: Job) => void;
  onError: (e: ApiError) => void;
  done: boolean;
  timer: number | null;
}

class Events {
  private socket: WebSocket | null = null;
  private open = false;
  private retryMs = 500;
  private reconnectTimer: number | null = null;
  private watches = new Map<number, Watch>();

  /**
   * Calls onUpdate with every change of the job until it ends; the last call carries the job read
   * over REST (with its artifacts). Returns a function that stops watching.
   */
  watch(
    kind: Job['kind'],
    id: number,
    onUpdate: (job: Job) => void,
    onError: (e: ApiError) => void = () => {},
  ): () => void {
    const w: Watch = { id, kind, onUpdate, onError, done: false, timer: null };
    this.watches.set(id, w);
    this.connect();
    if (this.open) this.subscribe(w);
    else this.poll(w);
    return () => this.stop(w);
  }

  private stop(w: Watch): void {
    w.done = true;
    if (w.timer !== null) clearTimeout(w.timer);
    if (this.watches.get(w.id) === w) this.watches.delete(w.id);
    if (this.open && this.socket) this.socket.send(JSON.stringify({ unsubscribe: { jobs: [w.id] } }));
  }

  private subscribe(w: Watch): void {
    this.socket?.send(JSON.stringify({ subscribe: { jobs: [w.id] } }));
    void this.read(w); // catch up with what happened before the subscription
  }

  /** One REST read; terminal states end the watch. */
  private async read(w: Watch): Promise<void> {
    try {
      const job = await api.get<Job>(`/${collection(w.kind)}/${w.id}`);
      this.deliver(w, job, true);
    } catch (e) {
      if (w.done) return;
      if (e instanceof ApiError && e.status !== 0 && e.status !== 503) {
        this.stop(w);
        w.onError(e);
      }
    }
  }

  private poll(w: Watch): void {
    if (w.done || this.open) return;
    void this.read(w).then(() => {
      if (!w.done && !this.open) w.timer = window.setTimeout(() => this.poll(w), 500);
    });
  }

  private deliver(w: Watch, job: Job, fromRest: boolean): void {
    if (w.done) return;
    if (terminal(job.state)) {
      if (!fromRest) {
        void this.read(w); // the full job, with its artifacts
        return;
      }
      this.stop(w);
    }
    w.onUpdate(job);
  }

  private connect(): void {
    if (this.socket || this.reconnectTimer !== null) return;
    let ws: WebSocket;
    try {
      const scheme = window.location.protocol === 'https:' ? 'wss:' : 'ws:';
      ws = new WebSocket(`${scheme}//${window.location.host}/api/v1/events`);
    } catch {
      this.scheduleReconnect();
      return;
    }
    this.socket = ws;
    ws.onopen = () => {
      this.open = true;
      this.retryMs = 500;
      for (const w of this.watches.values()) {
        if (w.timer !== null) clearTimeout(w.timer);
        w.timer = null;
        this.subscribe(w);
      }
    };
    ws.onmessage = (ev: MessageEvent) => {
      let msg: { type?: string; job?: Job };
      try {
        msg = JSON.parse(String(ev.data));
      } catch {
        return;
      }
      if (msg.type !== 'job' || !msg.job) return;
      const w = this.watches.get(msg.job.id);
      if (w && w.kind === msg.job.kind) this.deliver(w, msg.job, false);
    };
    ws.onclose = () => {
      this.socket = null;
      this.open = false;
      if (this.watches.size > 0) {
        for (const w of this.watches.values()) this.poll(w);
        this.scheduleReconnect();
      }
    };
    ws.onerror = () => {
      /* onclose follows and falls back to polling */
    };
  }

  private scheduleReconnect(): void {
    if (this.reconnectTimer !== null) return;
    this.reconnectTimer = window.setTimeout(() => {
      this.reconnectTimer = null;
      if (this.watches.size > 0) this.connect();
    }, this.retryMs);
    this.retryMs = Math.min(this.retryMs * 2, 10000);
  }
}

export const events = new Events();
