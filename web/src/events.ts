// Live job and flight updates: one WebSocket to /api/v1/events shared by every watcher, reconnecting
// with a growing delay; while the socket is not open, each watched job is polled every 500 ms instead
// (a flight every second). A job or flight is also read once after each (re)subscription, so a change
// made before it is never missed. Jobs: {"subscribe": {"jobs": [id]}} → {"type": "job", "job"};
// flights (docs/flights.md): {"subscribe": {"flights": [id]}} → {"type": "flight", "flight"}.
import { api, ApiError } from './api.ts';
import { flightEnded, type Flight } from './fly-model.ts';

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

/** What a watch follows: the subscription topic, the REST path, and when it ends. */
interface Topic<T> {
  topic: 'jobs' | 'flights';
  path: string;
  ended: (x: T) => boolean;
  pollMs: number;
}

interface Watch<T = unknown> {
  key: string;
  id: number;
  /** for jobs: the kind a message must have */
  kind: Job['kind'] | null;
  t: Topic<T>;
  onUpdate: (x: T) => void;
  onError: (e: ApiError) => void;
  done: boolean;
  timer: number | null;
}

class Events {
  private socket: WebSocket | null = null;
  private open = false;
  private retryMs = 500;
  private reconnectTimer: number | null = null;
  private watches = new Map<string, Watch>();

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
    const t: Topic<Job> = { topic: 'jobs', path: `/${collection(kind)}/${id}`, ended: (j) => terminal(j.state), pollMs: 500 };
    return this.add({ key: `jobs:${id}`, id, kind, t, onUpdate, onError, done: false, timer: null });
  }

  /**
   * Calls onUpdate with every change of the flight (at most every 200 ms, the server's pace) until it
   * ends (done or aborted); the last call carries the flight read over REST. Returns a function that
   * stops watching.
   */
  watchFlight(id: number, onUpdate: (f: Flight) => void, onError: (e: ApiError) => void = () => {}): () => void {
    const t: Topic<Flight> = { topic: 'flights', path: `/flights/${id}`, ended: (f) => flightEnded(f.state), pollMs: 1000 };
    return this.add({ key: `flights:${id}`, id, kind: null, t, onUpdate, onError, done: false, timer: null });
  }

  private add<T>(w: Watch<T>): () => void {
    const old = this.watches.get(w.key);
    if (old) this.stop(old, false);
    this.watches.set(w.key, w as Watch);
    this.connect();
    if (this.open) this.subscribe(w as Watch);
    else this.poll(w as Watch);
    return () => this.stop(w as Watch);
  }

  private stop(w: Watch, unsubscribe = true): void {
    w.done = true;
    if (w.timer !== null) clearTimeout(w.timer);
    if (this.watches.get(w.key) === w) this.watches.delete(w.key);
    if (unsubscribe && this.open && this.socket) this.socket.send(JSON.stringify({ unsubscribe: { [w.t.topic]: [w.id] } }));
  }

  private subscribe(w: Watch): void {
    this.socket?.send(JSON.stringify({ subscribe: { [w.t.topic]: [w.id] } }));
    void this.read(w); // catch up with what happened before the subscription
  }

  /** One REST read; terminal states end the watch. */
  private async read(w: Watch): Promise<void> {
    try {
      const x = await api.get<unknown>(w.t.path);
      this.deliver(w, x, true);
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
      if (!w.done && !this.open) w.timer = window.setTimeout(() => this.poll(w), w.t.pollMs);
    });
  }

  private deliver(w: Watch, x: unknown, fromRest: boolean): void {
    if (w.done) return;
    if (w.t.ended(x)) {
      if (!fromRest) {
        void this.read(w); // the full job (with its artifacts) or flight
        return;
      }
      this.stop(w);
    }
    w.onUpdate(x);
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
      let msg: { type?: string; job?: Job; flight?: Flight };
      try {
        msg = JSON.parse(String(ev.data));
      } catch {
        return;
      }
      if (msg.type === 'job' && msg.job) {
        const w = this.watches.get(`jobs:${msg.job.id}`);
        if (w && w.kind === msg.job.kind) this.deliver(w, msg.job, false);
      } else if (msg.type === 'flight' && msg.flight) {
        const w = this.watches.get(`flights:${msg.flight.id}`);
        if (w) this.deliver(w, msg.flight, false);
      }
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
