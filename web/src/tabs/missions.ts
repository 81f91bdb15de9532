// The Missions tab (issue 11).
import type { App, Tab } from '../state.ts';

export const missionsTab: Tab = {
  name: 'missions',
  title: 'Missions',
  mount(panel: HTMLElement, _app: App) {
    panel.innerHTML = '<p class="muted">Missions</p>';
  },
};
