// The inspector's rows for a selected volume: its isovalue as a slider over the data's value range
// and as a typed number (a slider's drag is sent as it moves, coalesced, and is one undoable step
// when released), what the grid is, and the note that the DM mesh has no volume occluders.

const round = (x) => String(Math.round(x * 1e4) / 1e4);

// Appends the rows to `root`; callbacks: onInput(value) while the slider moves or a number is
// typed, onCommit(before, after) once a gesture ends. Returns {update(isovalue)}.
export function appendVolumeRows(root, info, isovalue, { onInput, onCommit }) {
  const [lo, hi] = info.value_range;
  const row = document.createElement('div');
  row.className = 'row inspector-row';
  const name = document.createElement('span');
  name.textContent = 'isovalue';
  const slider = document.createElement('input');
  slider.type = 'range';
  slider.id = 'volume-isovalue';
  slider.min = String(lo);
  slider.max = String(hi);
  slider.step = String(info.voxel_type === 'float' ? (hi - lo) / 1000 || 1e-3 : (hi - lo) / 1000 > 1 ? 1 : 0.5);
  const number = document.createElement('input');
  number.type = 'text';
  number.inputMode = 'decimal';
  number.size = 7;
  number.id = 'volume-isovalue-number';
  row.append(name, slider, number);
  let before = isovalue;
  const show = (value) => {
    if (document.activeElement !== slider) slider.value = String(value);
    if (document.activeElement !== number) number.value = round(value);
  };
  slider.addEventListener('input', () => {
    number.value = round(Number(slider.value));
    onInput(Number(slider.value));
  });
  slider.addEventListener('change', () => {
    const after = Number(slider.value);
    if (after !== before) onCommit(before, after);
    before = after;
  });
  number.addEventListener('keydown', (event) => { if (event.key === 'Enter') number.blur(); });
  number.addEventListener('change', () => {
    const value = Number(number.value.replace(',', '.'));
    const valid = Number.isFinite(value) && value >= lo && value <= hi;
    number.classList.toggle('invalid', !valid);
    number.title = valid ? '' : `a number in the volume's values [${round(lo)}, ${round(hi)}]`;
    if (!valid || value === before) return;
    slider.value = String(value);
    onInput(value);
    onCommit(before, value);
    before = value;
  });
  const grid = document.createElement('div');
  grid.className = 'muted';
  grid.textContent = `volume: ${info.size.join(' × ')} ${info.voxel_type} voxels, values ${round(lo)} … ${round(hi)}`;
  const note = document.createElement('div');
  note.className = 'note volume-note';
  note.textContent = 'The lit mesh (DM) has no volume occluders: this volume casts no shadow in the 3D view. '
    + 'The server render shows its surface and its soft shadows.';
  root.append(row, grid, note);
  show(isovalue);
  return { update: (value) => { before = value; show(value); } };
}
