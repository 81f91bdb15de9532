// The app's shared state: the mission being edited and the latest plan. Tabs read it and subscribe.
import type L from 'leaflet';

export interface AppState {
  missionId: number | null;
  revision: number | null;
  /** the uavcover v1 mission document being edited */
  mission: Record<string, unknown> | null;
  planId: number | null;
}

type Listener = (s: AppState) => void;

export class App {
  state: AppState = { missionId: null, revision: null, mission: null, planId: null };
  private listeners: Listener[] = [];
  constructor(
    readonly map: L.Map,
    readonly showTab: (name: string) => void,
  ) {}
  update(patch: Partial<AppState>): void {
    this.state = { ...this.state, ...patch };
    for (const l of this.listeners) l(this.state);
  }
  subscribe(l: Listener): void {
    this.listeners.push(l);
  }
}

export interface Tab {
  name: string;
  title: string;
  mount(panel: HTMLElement, app: App): void;
  /** called when the tab is shown again */
  show?(app: App): void;
  hide?(app: App): void;
}
