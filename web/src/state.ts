// The app's shared state: the mission being edited and the latest plan. Tabs read it and subscribe.
import type L from 'leaflet';

export interface AppState {
  missionId: number | null;
  revision: number | null;
  /** the uavcover v1 mission document being edited */
  mission: Record<string, unknown> | null;
  planId: number | null;
  /** true while the Define tab holds changes to `mission` that are not saved as a revision yet */
  dirty?: boolean;
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

/** A panel object with its own show/hide, created when the tab is mounted. */
export interface Panel {
  show(): void;
  hide(): void;
}

/** The Tab of a panel class: mount creates the panel, show and hide go to it. */
export function panelTab(name: string, title: string, create: (panel: HTMLElement, app: App) => Panel): Tab {
  let current: Panel | null = null;
  return {
    name,
    title,
    mount(panel: HTMLElement, app: App) {
      current = create(panel, app);
    },
    show() {
      current?.show();
    },
    hide() {
      current?.hide();
    },
  };
}
