// The arm's blocks for Blockly, their words, and the toolbox. Words a 10-year-old reads, in
// the units the sliders show (degrees, millimetres, percent). Every word is a Blockly message
// (ARM_*), so a translation is one more message file (docs/studio.md, "Blocks").
import * as Blockly from "blockly/core";
import "blockly/blocks"; // repeat, variables, maths, procedures
import * as En from "blockly/msg/en";
import type { Places } from "../engine/messages";

/** The joints the dropdowns offer: the robot shown (the page sets it). */
let jointNames: { name: string; unit: string }[] = [{ name: "joint 0", unit: "deg" }];
export function setJoints(joints: { name: string; unit: string }[]): void {
  if (joints.length) jointNames = joints;
}

/** The pins the signal blocks offer: the robot shown's free ones first, then the rest of the
 * header (a program made for another arm keeps its pin; the engine says it is not free here). */
let pins: { free: { pin: number; name: string }[]; header: string[] } = { free: [{ pin: 19, name: "A5" }], header: [] };
export function setPins(free: { pin: number; name: string }[], header: string[]): void {
  pins = { free, header };
}
const pinOptions = (): [string, string][] => {
  const out: [string, string][] = pins.free.map((p) => [p.name, String(p.pin)]);
  pins.header.forEach((name, i) => {
    if (!pins.free.some((p) => p.pin === i)) out.push([`${name} (${Blockly.Msg.ARM_PIN_TAKEN})`, String(i)]);
  });
  return out.length ? out : [["A5", "19"]];
};

export const ARM_MESSAGES: Record<string, string> = {
  ARM_JOINT_TO: "turn %1 to %2",
  ARM_JOINT_BY: "turn %1 by %2",
  ARM_JOINTS: "move every joint to %1",
  ARM_TOOL_TO: "move the tool to x %1 y %2 z %3 mm",
  ARM_LINE_TO: "move the tool in a straight line to x %1 y %2 z %3 mm at %4 mm/s",
  ARM_GRIPPER_OPEN: "open the gripper",
  ARM_GRIPPER_CLOSE: "close the gripper",
  ARM_GRIPPER_TO: "open the gripper to %1 %%",
  ARM_SPEED: "set the speed to %1 %%",
  ARM_HOME: "go to the home pose",
  ARM_WAIT: "wait %1 seconds",
  ARM_COMMENT: "note: %1",
  ARM_RAW: "line with no block: %1",
  ARM_PEN: "the pen is %1 mm long, the paper at z %2 mm",
  ARM_PEN_DOWN: "pen down",
  ARM_PEN_UP: "pen up",
  ARM_PEN_TO: "move the pen in a straight line to x %1 y %2 mm",
  ARM_WRITE: "write %1 %2 mm wide at x %3 y %4",
  ARM_SHAPE: "draw %1 %2 mm wide at x %3 y %4",
  ARM_SHAPE_SQUARE: "a square",
  ARM_SHAPE_CIRCLE: "a circle",
  ARM_SHAPE_STAR: "a star",
  ARM_CATEGORY_PEN: "Pen",
  ARM_CATEGORY_SIGNALS: "Signals",
  ARM_OUTPUT: "set pin %1 %2",
  ARM_WAIT_INPUT: "wait until pin %1 is %2, at most %3 seconds",
  ARM_HIGH: "high",
  ARM_LOW: "low",
  ARM_PIN_TAKEN: "the arm's",
  ARM_TIP_OUTPUT: "A signal to another arm or a device (a conveyor's relay): the pin goes high or low once the moves before it have ended",
  ARM_TIP_WAIT_INPUT: "The arm keeps still until the pin reads high or low (another arm's signal, a light barrier); if that takes longer, it stops there",
  ARM_TIP_PEN: "A pen held in the gripper: how far its tip is below the tool point, and how high the paper lies. Say it before the other pen blocks",
  ARM_TIP_PEN_DOWN: "The pen straight down onto the paper, where it is: from now on it draws",
  ARM_TIP_PEN_UP: "The pen lifted off the paper, where it is: it moves without drawing",
  ARM_TIP_PEN_TO: "The pen along a straight line to a point on the paper: it draws when it is down",
  ARM_TIP_WRITE: "Text in a single-stroke font, its width on the paper and its centre: the pen goes down for each stroke",
  ARM_TIP_SHAPE: "A shape for a first lesson, its width and centre on the paper",
  ARM_CATEGORY_MOVE: "Move",
  ARM_CATEGORY_GRIPPER: "Gripper",
  ARM_CATEGORY_CONTROL: "Repeat",
  ARM_CATEGORY_VARIABLES: "Variables",
  ARM_CATEGORY_MATHS: "Numbers",
  ARM_CATEGORY_PROCEDURES: "My blocks",
  ARM_TIP_JOINT_TO: "Turn one joint to an angle (or slide it to a length), as its slider shows it",
  ARM_TIP_JOINT_BY: "Turn one joint by an angle from where it is (or slide it by a length)",
  ARM_TIP_JOINTS: "Every joint at once, in the slider's values, separated by commas (Teach makes this block from the pose shown)",
  ARM_TIP_TOOL_TO: "Move the tip of the tool to a point, in millimetres from the base: the arm works out its joints (inverse kinematics)",
  ARM_TIP_LINE_TO: "Move the tip of the tool along a straight line to a point, at a speed: the arm cuts the line into short moves (a pen draws it straight)",
  ARM_TIP_GRIPPER_TO: "0 % is closed, 100 % fully open",
  ARM_TIP_SPEED: "How fast the motors turn: 100 % is the arm's normal speed",
  ARM_TIP_HOME: "The robot's home pose, where its file says it rests",
  ARM_TIP_WAIT: "The arm keeps still this long before its next block (0 to 600 seconds)",
  ARM_TIP_COMMENT: "A note for people: the arm does nothing",
  ARM_TIP_RAW: "A line of the program that no block stands for: it is sent as it is written",
};

const unitOf = (i: number) => (jointNames[i]?.unit === "mm" ? "mm" : "°");
const jointOptions = (): [string, string][] => jointNames.map((j, i) => [j.name, String(i)]);

function jointBlock(msg: string, tip: string, colour: number) {
  return {
    init(this: Blockly.Block) {
      const [before, after] = Blockly.Msg[msg].split("%1");
      const between = after.split("%2")[0];
      const dropdown = new Blockly.FieldDropdown(jointOptions, (v: string) => {
        const label = this.getField("UNIT");
        if (label) label.setValue(unitOf(Number(v)));
        return v;
      });
      this.appendValueInput("VALUE").setCheck("Number").appendField(before.trim()).appendField(dropdown, "JOINT")
        .appendField(between.trim());
      this.appendDummyInput().appendField(new Blockly.FieldLabel(unitOf(0)), "UNIT");
      this.setInputsInline(true);
      this.setPreviousStatement(true);
      this.setNextStatement(true);
      this.setColour(colour);
      this.setTooltip(Blockly.Msg[tip]);
    },
  };
}

let defined = false;
/** Blockly's words and the arm's blocks (once). */
export function defineBlocks(): void {
  if (defined) return;
  defined = true;
  Blockly.setLocale(En as unknown as Record<string, string>);
  Object.assign(Blockly.Msg, ARM_MESSAGES);
  Blockly.Blocks["arm_joint_to"] = jointBlock("ARM_JOINT_TO", "ARM_TIP_JOINT_TO", 210);
  Blockly.Blocks["arm_joint_by"] = jointBlock("ARM_JOINT_BY", "ARM_TIP_JOINT_BY", 210);
  Blockly.common.defineBlocksWithJsonArray([
    { type: "arm_joints", message0: "%{BKY_ARM_JOINTS}", args0: [{ type: "field_input", name: "VALUES", text: "0, 90, -90", spellcheck: false }],
      previousStatement: null, nextStatement: null, colour: 210, tooltip: "%{BKY_ARM_TIP_JOINTS}" },
    { type: "arm_tool_to", message0: "%{BKY_ARM_TOOL_TO}", args0: [
      { type: "input_value", name: "X", check: "Number" }, { type: "input_value", name: "Y", check: "Number" },
      { type: "input_value", name: "Z", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 230, tooltip: "%{BKY_ARM_TIP_TOOL_TO}" },
    { type: "arm_line_to", message0: "%{BKY_ARM_LINE_TO}", args0: [
      { type: "input_value", name: "X", check: "Number" }, { type: "input_value", name: "Y", check: "Number" },
      { type: "input_value", name: "Z", check: "Number" }, { type: "input_value", name: "SPEED", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 230, tooltip: "%{BKY_ARM_TIP_LINE_TO}" },
    { type: "arm_home", message0: "%{BKY_ARM_HOME}", previousStatement: null, nextStatement: null, colour: 210, tooltip: "%{BKY_ARM_TIP_HOME}" },
    { type: "arm_gripper_open", message0: "%{BKY_ARM_GRIPPER_OPEN}", previousStatement: null, nextStatement: null, colour: 30 },
    { type: "arm_gripper_close", message0: "%{BKY_ARM_GRIPPER_CLOSE}", previousStatement: null, nextStatement: null, colour: 30 },
    { type: "arm_gripper_to", message0: "%{BKY_ARM_GRIPPER_TO}", args0: [{ type: "input_value", name: "PERCENT", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 30, tooltip: "%{BKY_ARM_TIP_GRIPPER_TO}" },
    { type: "arm_wait", message0: "%{BKY_ARM_WAIT}", args0: [{ type: "input_value", name: "SECONDS", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 120, tooltip: "%{BKY_ARM_TIP_WAIT}" },
    { type: "arm_speed", message0: "%{BKY_ARM_SPEED}", args0: [{ type: "input_value", name: "PERCENT", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 120, tooltip: "%{BKY_ARM_TIP_SPEED}" },
    { type: "arm_comment", message0: "%{BKY_ARM_COMMENT}", args0: [{ type: "field_input", name: "TEXT", text: "what happens next" }],
      previousStatement: null, nextStatement: null, colour: 60, tooltip: "%{BKY_ARM_TIP_COMMENT}" },
    { type: "arm_pen", message0: "%{BKY_ARM_PEN}", args0: [{ type: "input_value", name: "PEN", check: "Number" }, { type: "input_value", name: "Z", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_PEN}" },
    { type: "arm_pen_down", message0: "%{BKY_ARM_PEN_DOWN}", previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_PEN_DOWN}" },
    { type: "arm_pen_up", message0: "%{BKY_ARM_PEN_UP}", previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_PEN_UP}" },
    { type: "arm_pen_to", message0: "%{BKY_ARM_PEN_TO}", args0: [{ type: "input_value", name: "X", check: "Number" }, { type: "input_value", name: "Y", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_PEN_TO}" },
    { type: "arm_write", message0: "%{BKY_ARM_WRITE}", args0: [{ type: "field_input", name: "TEXT", text: "Hi", spellcheck: false },
      { type: "input_value", name: "WIDTH", check: "Number" }, { type: "input_value", name: "X", check: "Number" }, { type: "input_value", name: "Y", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_WRITE}" },
    { type: "arm_shape", message0: "%{BKY_ARM_SHAPE}", args0: [{ type: "field_dropdown", name: "SHAPE", options: [
      ["%{BKY_ARM_SHAPE_SQUARE}", "square"], ["%{BKY_ARM_SHAPE_CIRCLE}", "circle"], ["%{BKY_ARM_SHAPE_STAR}", "star"]] },
      { type: "input_value", name: "WIDTH", check: "Number" }, { type: "input_value", name: "X", check: "Number" }, { type: "input_value", name: "Y", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 280, tooltip: "%{BKY_ARM_TIP_SHAPE}" },
    { type: "arm_output", message0: "%{BKY_ARM_OUTPUT}", args0: [{ type: "field_dropdown", name: "PIN", options: pinOptions },
      { type: "field_dropdown", name: "LEVEL", options: [["%{BKY_ARM_HIGH}", "1"], ["%{BKY_ARM_LOW}", "0"]] }],
      previousStatement: null, nextStatement: null, colour: 160, tooltip: "%{BKY_ARM_TIP_OUTPUT}" },
    { type: "arm_wait_input", message0: "%{BKY_ARM_WAIT_INPUT}", args0: [{ type: "field_dropdown", name: "PIN", options: pinOptions },
      { type: "field_dropdown", name: "LEVEL", options: [["%{BKY_ARM_HIGH}", "1"], ["%{BKY_ARM_LOW}", "0"]] },
      { type: "input_value", name: "SECONDS", check: "Number" }],
      inputsInline: true, previousStatement: null, nextStatement: null, colour: 160, tooltip: "%{BKY_ARM_TIP_WAIT_INPUT}" },
    { type: "arm_raw", message0: "%{BKY_ARM_RAW}", args0: [{ type: "field_input", name: "TEXT", text: "", spellcheck: false }],
      previousStatement: null, nextStatement: null, colour: 0, tooltip: "%{BKY_ARM_TIP_RAW}" },
  ]);
}

const num = (n: number) => ({ shadow: { type: "math_number", fields: { NUM: n } } });

/** The toolbox: the arm's blocks first, then a beginner's control. Its points are where this
 * arm reaches (the engine's places: the MK2's tool at 240, 0, 150, the meArm's at 150, 0, 110). */
export function toolbox(p: Places | null = null): Blockly.utils.toolbox.ToolboxDefinition {
  const tool = p?.tool ?? [240, 0, 150], to = p?.line_to ?? [280, 0, 150];
  const at = p?.draw_at ?? [250, 0], width = p?.draw_width ?? 40;
  const pen = p?.pen ?? 120, z = p?.paper_z ?? 0;
  const penTo = [at[0] + width / 4, at[1]];
  const pin = String(pins.free[0]?.pin ?? 19);
  return {
    kind: "categoryToolbox",
    contents: [
      { kind: "category", name: "%{BKY_ARM_CATEGORY_MOVE}", colour: "210", contents: [
        { kind: "block", type: "arm_joint_to", inputs: { VALUE: num(30) } },
        { kind: "block", type: "arm_joint_by", inputs: { VALUE: num(30) } },
        { kind: "block", type: "arm_joints" },
        { kind: "block", type: "arm_tool_to", inputs: { X: num(tool[0]), Y: num(tool[1]), Z: num(tool[2]) } },
        { kind: "block", type: "arm_line_to", inputs: { X: num(to[0]), Y: num(to[1]), Z: num(to[2]), SPEED: num(30) } },
        { kind: "block", type: "arm_home" },
        { kind: "block", type: "arm_speed", inputs: { PERCENT: num(50) } },
        { kind: "block", type: "arm_comment" },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_GRIPPER}", colour: "30", contents: [
        { kind: "block", type: "arm_gripper_open" },
        { kind: "block", type: "arm_gripper_close" },
        { kind: "block", type: "arm_gripper_to", inputs: { PERCENT: num(50) } },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_PEN}", colour: "280", contents: [
        { kind: "block", type: "arm_pen", inputs: { PEN: num(pen), Z: num(z) } },
        { kind: "block", type: "arm_pen_down" },
        { kind: "block", type: "arm_pen_up" },
        { kind: "block", type: "arm_pen_to", inputs: { X: num(penTo[0]), Y: num(penTo[1]) } },
        { kind: "block", type: "arm_write", inputs: { WIDTH: num(width), X: num(at[0]), Y: num(at[1]) } },
        { kind: "block", type: "arm_shape", inputs: { WIDTH: num(width), X: num(at[0]), Y: num(at[1]) } },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_SIGNALS}", colour: "160", contents: [
        { kind: "block", type: "arm_output", fields: { PIN: pin, LEVEL: "1" } },
        { kind: "block", type: "arm_wait_input", fields: { PIN: pin, LEVEL: "1" }, inputs: { SECONDS: num(30) } },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_CONTROL}", colour: "120", contents: [
        { kind: "block", type: "controls_repeat_ext", inputs: { TIMES: num(3) } },
        { kind: "block", type: "arm_wait", inputs: { SECONDS: num(1) } },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_VARIABLES}", colour: "330", custom: "VARIABLE" },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_MATHS}", colour: "230", contents: [
        { kind: "block", type: "math_number", fields: { NUM: 10 } },
        { kind: "block", type: "math_arithmetic", inputs: { A: num(1), B: num(1) } },
      ] },
      { kind: "category", name: "%{BKY_ARM_CATEGORY_PROCEDURES}", colour: "290", custom: "PROCEDURE" },
    ],
  } as Blockly.utils.toolbox.ToolboxDefinition;
}
