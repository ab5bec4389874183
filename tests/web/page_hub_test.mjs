#!/usr/bin/env node
// Unit tests of the page's event hub and undo commands (web_client/src/event_hub.js, commands.js,
// undo_history.js; node:test, no browser): handlers run in order and can stop, an unknown event
// throws; on seeded random gesture histories, undoing every step gives back the state before each
// step and redoing gives the state after, also after the history was saved and taken back as JSON
// (steps saved before commands had a kind included).
import assert from 'node:assert/strict';
import test from 'node:test';

import { EventHub } from '../../web_client/src/event_hub.js';
import { FrameCommand, IsovalueCommand, MoveCommand, commandFromJson } from '../../web_client/src/commands.js';
import { UndoHistory } from '../../web_client/src/undo_history.js';
import { seeded as rng } from './seeded_random.mjs';


// The browser's localStorage for node: the history saves and restores through it.
globalThis.localStorage = {
  items: new Map(),
  getItem(key) { return this.items.has(key) ? this.items.get(key) : null; },
  setItem(key, value) { this.items.set(key, String(value)); },
  removeItem(key) { this.items.delete(key); },
};

test('handlers run in subscription order, once each, until stopped', () => {
  const hub = new EventHub();
  const heard = [];
  const stopA = hub.on('selection', (id) => heard.push(`a:${id}`));
  hub.on('selection', (id) => heard.push(`b:${id}`));
  hub.on('version', () => heard.push('version'));
  hub.emit('selection', 'box1');
  stopA();
  stopA(); // a second stop changes nothing
  hub.emit('selection', null);
  assert.deepEqual(heard, ['a:box1', 'b:box1', 'b:null']);
});

test('a handler that stops another during an event does not skip the rest of that event', () => {
  const hub = new EventHub();
  const heard = [];
  let stopC = null;
  hub.on('history', () => { heard.push('a'); stopC(); });
  hub.on('history', () => heard.push('b'));
  stopC = hub.on('history', () => heard.push('c'));
  hub.emit('history');
  hub.emit('history');
  assert.deepEqual(heard, ['a', 'b', 'c', 'a', 'b']);
});

test('an unknown event name throws, naming it', () => {
  const hub = new EventHub();
  assert.throws(() => hub.on('selected', () => {}), /no event named 'selected'/);
  assert.throws(() => hub.emit('verison'), /no event named 'verison'/);
});

// The page's edit target as a model: objects' transforms, volumes' isovalues, and a scene whose
// structural frames add or remove ids (each frame logged).
class Target {
  constructor() {
    this.poses = new Map([['a', { translate: [0, 0, 0] }], ['b', { translate: [1, 0, 0] }]]);
    this.isovalues = new Map([['a', 0.5], ['b', 0.5]]);
    this.ids = new Set(['a', 'b']);
    this.selected = null;
  }

  moveTo(id, pose) { this.poses.set(id, pose); }
  isovalueTo(id, value) { this.isovalues.set(id, value); }
  async structural(edits, selectId) {
    for (const edit of edits) {
      if (edit.op === 'add') { assert.ok(!this.ids.has(edit.id)); this.ids.add(edit.id); }
      else { assert.ok(this.ids.delete(edit.id)); }
    }
    this.selected = selectId;
  }

  snapshot() {
    return JSON.stringify({ poses: [...this.poses].sort(), isovalues: [...this.isovalues].sort(), ids: [...this.ids].sort() });
  }
}

// One random gesture done on `target` and recorded as the page records it.
async function gesture(random, history, target, n) {
  const r = random();
  const id = ['a', 'b'][Math.floor(random() * 2)];
  if (r < 0.4) {
    const before = target.poses.get(id);
    const after = { translate: [random(), random(), random()] };
    const command = new MoveCommand(id, before, after);
    command.do(target);
    history.record(command);
  } else if (r < 0.6) {
    const before = target.isovalues.get(id);
    const after = random();
    target.isovalueTo(id, after); // a slider's gesture: already shown when it is recorded
    history.record(new IsovalueCommand(id, before, after));
  } else {
    const added = `n${n}`;
    await history.execute(new FrameCommand({ redo: [{ op: 'add', id: added }], undo: [{ op: 'remove', id: added }] },
      `add ${added}`, { redo: added, undo: null }), target);
  }
}

test('undo gives back each state before, redo each state after (seeded random histories, kept as JSON)', async () => {
  for (let seed = 1; seed <= 100; ++seed) {
    const random = rng(seed);
    const hub = new EventHub();
    let announced = 0;
    hub.on('history', () => ++announced);
    const history = new UndoHistory(hub);
    history.restore(`s${seed}.scene`, 0);
    const target = new Target();
    const states = [target.snapshot()];
    const steps = 1 + Math.floor(random() * 12);
    for (let n = 0; n < steps; ++n) {
      await gesture(random, history, target, n);
      states.push(target.snapshot());
    }
    assert.equal(announced, steps, `seed ${seed}: one history event per step`);
    // Taken back from storage as the next page load does: the same steps, as commands.
    history.save(7);
    const again = new UndoHistory(hub);
    again.restore(`s${seed}.scene`, 7);
    assert.equal(again.done.length, steps);
    const undos = 1 + Math.floor(random() * steps);
    for (let k = 1; k <= undos; ++k) {
      await again.undo(target);
      assert.equal(target.snapshot(), states[steps - k], `seed ${seed}: after ${k} undos`);
    }
    assert.equal(again.canUndo(), undos < steps);
    for (let k = undos - 1; k >= 0; --k) {
      await again.redo(target);
      assert.equal(target.snapshot(), states[steps - k], `seed ${seed}: redo back to step ${steps - k}`);
    }
    assert.equal(again.canRedo(), false);
  }
});

test('a new step after an undo drops the steps undone; a failed frame is not recorded', async () => {
  const history = new UndoHistory();
  const target = new Target();
  history.record(new MoveCommand('a', { t: 0 }, { t: 1 }));
  await history.undo(target);
  assert.ok(history.canRedo());
  history.record(new MoveCommand('a', { t: 0 }, { t: 2 }));
  assert.ok(!history.canRedo());
  const refused = new FrameCommand({ redo: [{ op: 'remove', id: 'zz' }], undo: [] }, 'remove zz', { redo: null, undo: null });
  await assert.rejects(history.execute(refused, target));
  assert.equal(history.done.length, 1);
  await history.undo(target);
  assert.deepEqual(target.poses.get('a'), { t: 0 });
  assert.equal(history.undo(target), null);
});

test('steps saved before commands had a kind are read by their shape; others are dropped', () => {
  const frame = commandFromJson({ frame: { redo: [1], undo: [2] }, label: 'add x', select: { redo: 'x', undo: null } });
  assert.ok(frame instanceof FrameCommand);
  assert.deepEqual(frame.toJSON(), { kind: 'frame', frame: { redo: [1], undo: [2] }, label: 'add x', select: { redo: 'x', undo: null } });
  const iso = commandFromJson({ id: 'v', isovalue: { before: 0.2, after: 0.7 } });
  assert.deepEqual(iso.toJSON(), { kind: 'isovalue', id: 'v', before: 0.2, after: 0.7 });
  const move = commandFromJson({ id: 'light:l', before: { polygon: [] }, after: { polygon: [[0, 0, 0]] } });
  assert.ok(move instanceof MoveCommand);
  for (const bad of [null, 3, {}, { kind: 'move', id: 7, before: {}, after: {} }, { kind: 'spin' }]) assert.equal(commandFromJson(bad), null);
  for (const command of [frame, iso, move]) assert.deepEqual(commandFromJson(JSON.parse(JSON.stringify(command))), command);
});
