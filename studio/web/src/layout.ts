// The page's layout for its screen, with the 3D view always the largest thing on it and STOP
// always in the header (docs/studio.md, "Every screen"):
// - wide (1500 px and up: desktops): panels left and right of the view, plots below;
// - dock (a laptop, a Chromebook, a tablet held sideways): the view, and beside it one panel
//   with tabs (Joints, IK, Program, Arm, Robot);
// - stacked (a tablet held upright, a phone): the view on top, the tabs below it, the plots in
//   a tab of their own.
// A low window (under 800 px) also puts the plots in a tab, and one under 1360 px wide the
// robot's menus (in the Robot tab: with them the header needs about 1,350 px). The panels' sections move between
// their home in the page and the tabs; their controls and listeners go with them.
import { $ } from "./page/dom";
import { store, stored } from "./page/environment";

export type Mode = "wide" | "dock" | "stacked";

/** The layout for a window of w x h CSS pixels. */
export function modeFor(w: number, h: number): Mode {
  if (w >= 1500) return "wide";
  if (w < 700 || (h > w && w < 1100)) return "stacked";
  return "dock";
}

interface Tab {
  id: string;
  label: string;
  title: string;
  // the page's parts this tab holds; `plots` and `menus` only when the layout moves them
  parts: string[];
}

const TABS: Tab[] = [
  { id: "joints", label: "Joints", title: "Move the arm joint by joint; where its tool is", parts: ["cell-arms-section", "joints-section", "jog-section", "tool-section"] },
  { id: "ik", label: "IK", title: "Inverse kinematics: put the tool at a target", parts: ["ik-section"] },
  { id: "program", label: "Program", title: "Write, open and run a program", parts: ["cell-section", "program-section", "draw-section"] },
  { id: "arm", label: "Arm", title: "The real arm or the virtual Nano: connect, send, flash, the experiment", parts: ["arm-section", "experiment-section"] },
  { id: "robot", label: "Robot", title: "Choose or open a robot, its scene, its DH table", parts: ["robot-tools", "scene-edit-section", "dh-section"] },
  { id: "plots", label: "Plots", title: "The program's time line as plots", parts: ["plots-panel"] },
];
const MENUS = "robot-tools"; // the robot's menus: in the header unless the layout is stacked
const PLOTS = "plots-panel"; // the plots: below the view unless the layout puts them in a tab
const KEY = "articula.studio.tab";

export class Layout {
  mode: Mode | null = null;
  plotsInTab = false;
  menusInHeader = true;
  active: string;
  onChange: () => void = () => {};
  private homes = new Map<string, Comment>();
  private panels = new Map<string, HTMLElement>();
  private buttons = new Map<string, HTMLButtonElement>();

  constructor() {
    // every part's home: a marker where it sits in the page as written (index.html)
    for (const tab of TABS)
      for (const id of tab.parts) {
        const part = $(id);
        const mark = document.createComment(`home of #${id}`);
        part.before(mark);
        this.homes.set(id, mark);
      }
    const list = $("dock-tabs");
    const body = $("dock-body");
    for (const tab of TABS) {
      const button = document.createElement("button");
      button.id = `tab-${tab.id}`;
      button.className = "tab";
      button.setAttribute("role", "tab");
      button.setAttribute("aria-controls", `tabpanel-${tab.id}`);
      button.title = tab.title;
      button.textContent = tab.label;
      button.addEventListener("click", () => this.show(tab.id, true));
      list.append(button);
      const panel = document.createElement("div");
      panel.id = `tabpanel-${tab.id}`;
      panel.className = "tabpanel";
      panel.setAttribute("role", "tabpanel");
      panel.setAttribute("aria-labelledby", button.id);
      body.append(panel);
      this.buttons.set(tab.id, button);
      this.panels.set(tab.id, panel);
    }
    // the keyboard in the tab list: arrows, Home and End move to a tab and show it
    list.addEventListener("keydown", (e) => {
      const shown = this.visibleTabs();
      const i = shown.indexOf(this.active);
      const next = { ArrowRight: i + 1, ArrowDown: i + 1, ArrowLeft: i - 1, ArrowUp: i - 1, Home: 0, End: shown.length - 1 }[e.key];
      if (next === undefined) return;
      e.preventDefault();
      this.show(shown[(next + shown.length) % shown.length], true);
      this.buttons.get(this.active)!.focus();
    });
    const saved = stored(KEY);
    this.active = TABS.some((t) => t.id === saved) ? saved! : "joints";
    new ResizeObserver(() => this.apply()).observe(document.documentElement);
    // the robot's name in the header takes the room the project's name leaves: cut to a letter
    // or two ("M") it says nothing, so it goes (its box stays: no loop with the observer)
    const name = $("robot-name");
    new ResizeObserver(() => name.classList.toggle("squeezed", name.clientWidth < 90 && name.scrollWidth > name.clientWidth))
      .observe(name);
    window.addEventListener("resize", () => this.apply());
    this.apply();
  }

  /** Lays the page out for the window's size now (a no-op when nothing changes). */
  apply(): void {
    const w = window.innerWidth, h = window.innerHeight;
    const mode = modeFor(w, h);
    // (below 800 px the plots strip would leave the blocks a sliver: a 1366x768 lab PC)
    const plotsInTab = mode === "stacked" || h < 800;
    const menusInHeader = w >= 1360; // else they push the header's chips off: the Robot tab holds them
    if (mode === this.mode && plotsInTab === this.plotsInTab && menusInHeader === this.menusInHeader) return;
    this.menusInHeader = menusInHeader;
    this.mode = mode;
    this.plotsInTab = plotsInTab;
    const body = document.body;
    body.classList.remove("layout-wide", "layout-dock", "layout-stacked");
    body.classList.add(`layout-${mode}`);
    body.classList.toggle("plots-tab", plotsInTab);
    $("left").hidden = $("right").hidden = mode !== "wide";
    $("dock").hidden = mode === "wide";
    for (const tab of TABS)
      for (const id of tab.parts) {
        const home = mode === "wide" || (id === MENUS && menusInHeader) || (id === PLOTS && !plotsInTab);
        if (home) this.homes.get(id)!.after($(id));
        else this.panels.get(tab.id)!.append($(id));
      }
    for (const tab of TABS) this.buttons.get(tab.id)!.hidden = !this.panels.get(tab.id)!.childElementCount;
    if (!this.visibleTabs().includes(this.active)) this.active = "joints";
    this.show(this.active, false);
  }

  /** Shows the tab that holds the page's part `id` (a section, a control in it); nothing in
   * the wide layout, where every panel is on screen. */
  reveal(id: string): void {
    if (this.mode === "wide") return;
    for (const [tab, panel] of this.panels) if (panel.contains(document.getElementById(id))) return this.show(tab, false);
  }

  private visibleTabs(): string[] {
    return TABS.map((t) => t.id).filter((id) => !this.buttons.get(id)!.hidden);
  }

  private show(id: string, chosen: boolean): void {
    this.active = id;
    for (const [tab, button] of this.buttons) {
      const on = tab === id;
      button.setAttribute("aria-selected", String(on));
      button.tabIndex = on ? 0 : -1;
      button.classList.toggle("active-tab", on);
      this.panels.get(tab)!.hidden = !on;
    }
    if (chosen) store(KEY, id);
    this.onChange();
  }
}
