// The Define tab (issue 11).
import type { App, Tab } from '../state.ts';

export const defineTab: Tab = {
  name: 'define',
  title: 'Define',
  mount(panel: HTMLElement, _app: App) {
    panel.innerHTML = '<p class="muted">Define</p>';
  },
};
