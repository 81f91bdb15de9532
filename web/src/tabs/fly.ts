// The Fly tab (issue 11): a placeholder until live execution arrives; it lists the plan's UAVs.
import { api } from '../api.ts';
import type { Job } from '../events.ts';
import { el } from '../job-ui.ts';
import { uavColour } from '../palette.ts';
import type { App, Tab } from '../state.ts';

export const flyTab: Tab = {
  name: 'fly',
  title: 'Fly',
  mount(panel: HTMLElement, app: App) {
    const box = el('div', { class: 'plan-fly', 'data-testid': 'fly-placeholder' });
    box.append(el('p', {}, 'Fly: select UAVs, start and supervise — arrives with live execution.'));
    const list = el('ul', { class: 'plan-fly-list', 'data-testid': 'fly-uavs' });
    const note = el('p', { class: 'muted' });
    box.append(note, list);
    panel.append(box);
    let shown: number | null = -1;
    const refresh = async () => {
      const id = app.state.planId;
      if (id === shown) return;
      shown = id;
      list.replaceChildren();
      if (id === null) {
        note.textContent = 'No plan yet: plan the mission in the Plan tab.';
        return;
      }
      try {
        const job = await api.get<Job>(`/plans/${id}`);
        const uavs = (job.result.uavs as { id: string; length_m?: number }[] | undefined) ?? [];
        note.textContent = `Plan #${id} (mission #${job.mission_id}, revision ${job.revision}): ${uavs.length} UAV${uavs.length === 1 ? '' : 's'}.`;
        uavs.forEach((u, i) => {
          const li = el('li', { 'data-uav': u.id });
          const sw = el('span', { class: 'plan-swatch' });
          sw.style.background = uavColour(i);
          li.append(sw, document.createTextNode(`${u.id}${u.length_m !== undefined ? ` — ${(u.length_m / 1000).toFixed(2)} km` : ''}`));
          list.append(li);
        });
      } catch (e) {
        note.textContent = `Plan #${id} cannot be read: ${(e as Error).message}`;
      }
    };
    app.subscribe(() => void refresh());
    this.show = () => void refresh();
  },
};
