// Entry point: the map on the right, a toolbar of tabs on the left (Apostolidis et al. 2022 Fig. 19).
import './style.css';
import { createMap } from './map.ts';
import { App, type Tab } from './state.ts';
import { missionsTab } from './tabs/missions.ts';
import { defineTab } from './tabs/define.ts';
import { planTab } from './tabs/plan.ts';
import { flyTab } from './tabs/fly.ts';

const tabs: Tab[] = [missionsTab, defineTab, planTab, flyTab];
const nav = document.getElementById('tabs')!;
const panel = document.getElementById('panel')!;
const panels = new Map<string, HTMLElement>();
let current: Tab | null = null;

function showTab(name: string): void {
  const tab = tabs.find((t) => t.name === name);
  if (!tab) return;
  if (current && current !== tab) current.hide?.(app);
  for (const [n, el] of panels) el.hidden = n !== name;
  for (const b of nav.querySelectorAll('button')) {
    b.setAttribute('aria-selected', String(b.dataset.tab === name));
    b.tabIndex = b.dataset.tab === name ? 0 : -1; // one tab stop for the tab list; arrows move in it
  }
  current = tab;
  tab.show?.(app);
  syncUrl();
}

/** A ?mission=ID link is kept in the address until that mission is open (the Plan tab opens it). */
let linkPending = new URLSearchParams(window.location.search).has('mission');

/** The open mission and tab live in the address (?mission=ID#plan), so a reload reopens them. */
function syncUrl(): void {
  const url = new URL(window.location.href);
  const id = app.state.missionId;
  if (id !== null) linkPending = false;
  if (id !== null) url.searchParams.set('mission', String(id));
  else if (!linkPending) url.searchParams.delete('mission');
  url.hash = current ? current.name : '';
  if (url.href !== window.location.href) window.history.replaceState(null, '', url.href);
}

const app = new App(createMap(document.getElementById('map')!), showTab);
for (const tab of tabs) {
  const button = document.createElement('button');
  button.type = 'button';
  button.role = 'tab';
  button.id = `tab-${tab.name}`;
  button.setAttribute('aria-controls', `panel-${tab.name}`);
  button.dataset.tab = tab.name;
  button.textContent = tab.title;
  button.addEventListener('click', () => showTab(tab.name));
  nav.appendChild(button);
  const el = document.createElement('div');
  el.className = 'tab-panel';
  el.dataset.tab = tab.name;
  el.id = `panel-${tab.name}`;
  el.setAttribute('role', 'tabpanel');
  el.setAttribute('aria-labelledby', `tab-${tab.name}`);
  el.hidden = true;
  panel.appendChild(el);
  panels.set(tab.name, el);
  tab.mount(el, app);
}
// WAI-ARIA tabs: Left/Right (and Home/End) move to the neighbouring tab and select it
nav.addEventListener('keydown', (e: KeyboardEvent) => {
  const buttons = [...nav.querySelectorAll<HTMLButtonElement>('button[role=tab]')];
  const at = buttons.indexOf(document.activeElement as HTMLButtonElement);
  if (at < 0) return;
  const to = e.key === 'ArrowRight' ? (at + 1) % buttons.length : e.key === 'ArrowLeft' ? (at + buttons.length - 1) % buttons.length : e.key === 'Home' ? 0 : e.key === 'End' ? buttons.length - 1 : -1;
  if (to < 0) return;
  e.preventDefault();
  buttons[to].focus();
  showTab(buttons[to].dataset.tab!);
});
// unsaved edits of the Define tab: the browser asks before a reload or leaving the page
window.addEventListener('beforeunload', (e) => {
  if (app.state.dirty && app.state.mission) {
    e.preventDefault();
    e.returnValue = '';
  }
});
app.subscribe(syncUrl);
const initial = window.location.hash.slice(1);
showTab(tabs.some((t) => t.name === initial) ? initial : 'missions');
