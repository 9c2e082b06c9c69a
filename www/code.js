// A code editor of the page's program modes (the Script mode's PLaSM, the HyperFun mode's
// programs): a text area with a gutter of line numbers marked where the last run had errors or
// warnings, kept in this browser as it is typed, Ctrl+Enter to run, Tab to indent (after Esc, Tab
// leaves the editor, the usual way out of a code editor), and text put in through the editor's
// own editing so that its undo (Ctrl+Z) brings back what was replaced.
import { $, say } from './ui.js';
import { storage } from './storage.js';

/**
 * Sets up the editor `ids.editor` with its gutter `ids.gutter`, kept under `key`; `what` names the
 * text in messages ("script"), `mode` is the workspace that shows it, `onRun()` runs it and
 * `onInput()` (optional) is told of each edit.
 */
export function codeEditor(app, { ids, key, what, exportName, mode, onRun, onInput = () => {} }) {
  const editor = $(ids.editor);
  const gutter = $(ids.gutter);
  let marks = new Map(); // line → 'error' | 'warn'
  let gutterLines = 0;
  const renderGutter = (force = false) => {
    const n = editor.value.split('\n').length;
    if (!force && n === gutterLines) return;
    gutterLines = n;
    const out = [];
    for (let i = 1; i <= n; i++) {
      const mark = marks.get(i);
      out.push(mark ? `<span class="${mark}" title="${mark === 'error' ? 'error' : 'warning'}">${i}</span>` : String(i));
    }
    gutter.innerHTML = out.join('\n') + '\n\n';
    gutter.scrollTop = editor.scrollTop;
  };
  editor.addEventListener('scroll', () => { gutter.scrollTop = editor.scrollTop; });
  let saveTimer = 0;
  editor.addEventListener('input', () => {
    renderGutter();
    clearTimeout(saveTimer);
    saveTimer = setTimeout(() => {
      if (!storage.set(key, editor.value)) say(`The ${what} could not be saved in this browser; use Export → ${exportName}.`, 'warn');
    }, 300);
    onInput();
  });
  addEventListener('pagehide', () => storage.set(key, editor.value));

  // The place (line, column from 1, in characters as the interpreters count them) as an offset
  // in the editor's text (in UTF-16 units, as the text area counts them).
  const offsetOf = (line, column) => {
    const lines = editor.value.split('\n');
    let offset = 0;
    for (let i = 0; i < Math.min(line - 1, lines.length); i++) offset += lines[i].length + 1;
    const chars = Array.from(lines[line - 1] ?? '').slice(0, Math.max(column - 1, 0));
    return Math.min(offset + chars.join('').length, editor.value.length);
  };
  const goTo = (line, column) => {
    const at = offsetOf(line, column);
    editor.focus();
    editor.setSelectionRange(at, Math.min(at + 1, editor.value.length));
    const lineHeight = parseFloat(getComputedStyle(editor).lineHeight) || 19;
    editor.scrollTop = Math.max(0, (line - 4) * lineHeight);
  };

  let tabEscapes = false;
  editor.addEventListener('keydown', (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key === 'Enter') {
      e.preventDefault();
      onRun();
      return;
    }
    if (e.key === 'Escape') {
      tabEscapes = true;
      return;
    }
    if (e.key === 'Tab' && !tabEscapes && !e.shiftKey && !e.ctrlKey && !e.altKey && !e.metaKey) {
      e.preventDefault();
      document.execCommand?.('insertText', false, '  ') || editor.setRangeText('  ', editor.selectionStart, editor.selectionEnd, 'end');
      return;
    }
    tabEscapes = false;
  });
  editor.addEventListener('focus', () => { tabEscapes = false; });
  renderGutter(true);

  return {
    editor,
    text: () => editor.value,
    renderGutter,
    goTo,
    /** Marks lines (line → 'error' | 'warn') in the gutter. */
    mark: (lines) => {
      marks = lines;
      renderGutter(true);
    },
    /** Puts `text` in the editor (kept in this browser). */
    load: (text) => {
      // In the mode, through the editor's own editing, so that its undo (Ctrl+Z) brings back the
      // text replaced; otherwise (a link opened at start-up, the editor hidden) set plainly.
      if (editor.value !== text) {
        let typed = false;
        if (app.workspace() === mode) {
          editor.focus();
          if (document.activeElement === editor) {
            editor.select();
            typed = document.execCommand('insertText', false, text) && editor.value === text;
          }
        }
        if (!typed) editor.value = text;
        editor.setSelectionRange(0, 0);
        editor.scrollTop = 0;
      }
      storage.set(key, text);
      renderGutter(true);
    },
  };
}
