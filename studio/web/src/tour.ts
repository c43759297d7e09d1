// A first-run tour of five steps: what the panels are for, and where the exercises are. Shown once (remembered in the
// browser), again from the Tour button.
interface Step {
  target: string;
  title: string;
  text: string;
  touch?: string; // the text where a finger is the pointer (a tablet, a phone)
}

const touchFirst = () => window.matchMedia("(pointer: coarse)").matches;

const STEPS: Step[] = [
  { target: "view-wrap", title: "The arm in 3D",
    text: "Drag to orbit, right-drag to pan, scroll to zoom (or the arrow keys and + -). Fit view frames the arm; Frames shows each DH frame's axes and number.",
    touch: "One finger orbits, two fingers pan, a pinch zooms. Fit view frames the arm; Frames shows each DH frame's axes and number." },
  { target: "joints-section", title: "Move it joint by joint",
    text: "Every joint variable of the DH table has a slider. The table and the tool pose update as you move: watch which axis each row turns about." },
  { target: "ik-section", title: "Tell it where to go",
    text: "Type a target, or tick IK target and drag the ball: inverse kinematics finds the joint values. Animate JT shows the thesis's Jacobian transpose at work." },
  { target: "program-section", title: "Program it",
    text: "Open an example or write commands (L 0 30, M 0 60 -60, P 200 0 150). Run plays them with the real controller's timing; the ghost shows the ideal pose, Teach records the current one." },
  { target: "program-section", title: "Try an exercise",
    text: "The examples menu starts with the exercises: a task for the arm, and Check says whether your program does it. Undo (\u21B6) takes back any change; Projects keeps your work." },
];
import { store, stored } from "./page/environment";

const KEY = "articula.studio.tour.done";

/** Shows the tour (once, unless `force`); `reveal` brings a step's part on screen (a tab). */
export function startTour(force: boolean, reveal: (id: string) => void = () => {}): void {
  if (!force && stored(KEY)) return; // (no storage: it shows every time)
  const tour = document.getElementById("tour")!;
  let i = 0;
  const show = () => {
    document.querySelectorAll(".tour-highlight").forEach((e) => e.classList.remove("tour-highlight"));
    const s = STEPS[i];
    reveal(s.target);
    document.getElementById(s.target)?.classList.add("tour-highlight");
    document.getElementById("tour-step")!.textContent = `${i + 1} of ${STEPS.length}`;
    document.getElementById("tour-title")!.textContent = s.title;
    document.getElementById("tour-text")!.textContent = s.touch && touchFirst() ? s.touch : s.text;
    document.getElementById("tour-next")!.textContent = i === STEPS.length - 1 ? "Start" : "Next";
    tour.hidden = false;
  };
  const end = () => {
    tour.hidden = true;
    document.querySelectorAll(".tour-highlight").forEach((e) => e.classList.remove("tour-highlight"));
    store(KEY, "1");
  };
  document.getElementById("tour-next")!.onclick = () => (++i < STEPS.length ? show() : end());
  document.getElementById("tour-skip")!.onclick = end;
  show();
}
