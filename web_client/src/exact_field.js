// One number of the inspector as a text field that never changes a value nobody typed: it shows
// the number rounded to 4 decimals, the whole number while focused, and reads back the exact
// number it was given unless its text was edited (then the typed text). The owner commits on
// `change` (Enter or leaving the field) and marks bad numbers itself.

const SHORT = 1e4;
export const shortNumber = (x) => String(Math.round(x * SHORT) / SHORT);

export class ExactField {
  // key: the field's name (data-key, for tests and the owner); onChange: called on a commit.
  constructor(key, onChange, size = 6) {
    const input = document.createElement('input');
    input.type = 'text';
    input.inputMode = 'decimal';
    input.size = size;
    input.dataset.key = key;
    this.input = input;
    this.exact = NaN;
    this.shown = '';
    // The whole number, selected (typing replaces it, as it would the rounded text).
    input.addEventListener('focus', () => {
      this.display(String(this.exact));
      input.select();
    });
    input.addEventListener('change', () => {
      // The typed number is now the field's own (until the owner's next set()).
      const typed = this.read();
      if (Number.isFinite(typed)) {
        this.exact = typed;
        this.shown = this.input.value;
      }
      onChange();
    });
    input.addEventListener('blur', () => { if (!this.edited()) this.display(shortNumber(this.exact)); });
    input.addEventListener('keydown', (event) => { if (event.key === 'Enter') input.blur(); });
  }

  // A new exact value, shown unless the person is typing in the field.
  set(value) {
    this.exact = value;
    if (document.activeElement !== this.input) this.display(shortNumber(value));
  }

  edited() {
    return this.input.value !== this.shown;
  }

  // The exact number given when the text is as shown, else the typed one (NaN if not a number).
  read() {
    if (!this.edited()) return this.exact;
    const text = this.input.value.trim().replace(',', '.');
    return text === '' ? NaN : Number(text);
  }

  display(text) {
    this.input.value = text;
    this.shown = text;
  }
}
