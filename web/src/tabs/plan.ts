// The Plan tab (issue 11).
import type { App, Tab } from '../state.ts';

export const planTab: Tab = {
  name: 'plan',
  title: 'Plan',
  mount(panel: HTMLElement, _app: App) {
    panel.innerHTML = '<p class="muted">Plan</p>';
  },
};
