// The Fly tab (issue 11).
import type { App, Tab } from '../state.ts';

export const flyTab: Tab = {
  name: 'fly',
  title: 'Fly',
  mount(panel: HTMLElement, _app: App) {
    panel.innerHTML = '<p class="muted">Fly</p>';
  },
};
