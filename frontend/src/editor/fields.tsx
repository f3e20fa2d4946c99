/**
 * Small labelled inputs the inspector panels share: a field that commits on Enter or when it
 * loses focus (ids, lists, multi-line specs), and the expression field with completion of
 * quantity names and inline parse errors.
 */
import { useCombobox } from "downshift";
import { type KeyboardEvent, type ReactNode, type SelectHTMLAttributes, useEffect, useId, useLayoutEffect, useMemo, useRef, useState } from "react";

import { applyCompletion, checkExpr, completions } from "./expr";
import { type Choice, CHOICES_SHOWN, filterChoices, movesThroughOptions } from "./pickers";

/**
 * A native drop-down that commits on a real choice (a click on an option, Enter, or focus
 * leaving it), not on each option the arrow keys or type-ahead pass: Chromium fires "change"
 * for every one of those, which used to save and re-validate the draft each time. Escape
 * goes back to the saved value.
 */
export function CommitSelect({
  value,
  onCommit,
  children,
  onKeyDown,
  onBlur,
  ...rest
}: Omit<SelectHTMLAttributes<HTMLSelectElement>, "value" | "onChange"> & {
  value: string;
  onCommit: (value: string) => void;
  children: ReactNode;
}) {
  const [pending, setPending] = useState<string | null>(null);
  const byKeys = useRef(false);
  const commit = (next: string) => {
    setPending(null);
    if (next !== value) onCommit(next);
  };
  return (
    <select
      {...rest}
      value={pending ?? value}
      data-pending={pending !== null ? "true" : undefined}
      onKeyDown={(e) => {
        byKeys.current = movesThroughOptions(e.key, e);
        if (e.key === "Enter" && pending !== null) {
          e.preventDefault();
          commit(pending);
        } else if (e.key === "Escape" && pending !== null) {
          e.preventDefault();
          setPending(null);
        }
        onKeyDown?.(e);
      }}
      onPointerDown={() => {
        byKeys.current = false;
      }}
      onChange={(e) => {
        const next = e.target.value;
        if (byKeys.current) {
          byKeys.current = false;
          setPending(next === value ? null : next);
        } else commit(next);
      }}
      onBlur={(e) => {
        if (pending !== null) commit(pending);
        onBlur?.(e);
      }}
    >
      {children}
    </select>
  );
}

/**
 * A searchable picker (WAI-ARIA combobox, downshift): typing narrows the choices by id or
 * title, the arrow keys only highlight, and Enter or a click commits the highlighted choice.
 * Leaving the field (or Escape) keeps the saved value.
 */
// Length: one downshift combobox: its state reducer beside the markup it drives.
export function Picker({
  id,
  label,
  value,
  choices,
  onCommit,
  describedBy,
  testId,
}: {
  id: string;
  label: ReactNode;
  value: string;
  choices: Choice[];
  onCommit: (value: string) => void;
  describedBy?: string;
  testId?: string;
}) {
  const [query, setQuery] = useState("");
  const selected = choices.find((c) => c.value === value) ?? (value ? { value, label: `${value} (unknown)` } : null);
  const found = useMemo(() => filterChoices(choices, query), [choices, query]);
  const items = found.slice(0, CHOICES_SHOWN);
  const { isOpen, highlightedIndex, getLabelProps, getInputProps, getMenuProps, getItemProps, getToggleButtonProps } = useCombobox<Choice>({
    items,
    inputId: id,
    labelId: `${id}-label`,
    menuId: `${id}-menu`,
    toggleButtonId: `${id}-toggle`,
    getItemId: (index) => `${id}-option-${index}`,
    itemToString: (c) => (c ? c.label : ""),
    itemToKey: (c) => c?.value,
    selectedItem: selected,
    onInputValueChange: ({ inputValue, type }) => {
      if (type === useCombobox.stateChangeTypes.InputChange) setQuery(inputValue ?? "");
    },
    onIsOpenChange: ({ isOpen: open }) => {
      if (!open) setQuery("");
    },
    onSelectedItemChange: ({ selectedItem }) => {
      if (selectedItem && selectedItem.value !== value) onCommit(selectedItem.value);
    },
    stateReducer: (_state, { type, changes }) => {
      // Leaving the field never picks the highlighted choice: only Enter or a click commits.
      if (type === useCombobox.stateChangeTypes.InputBlur) {
        return { ...changes, selectedItem: selected, inputValue: selected?.label ?? "" };
      }
      return changes;
    },
  });
  return (
    <div className="picker" data-testid={testId}>
      <label {...getLabelProps()}>{label}</label>
      <div className="picker-field">
        <input {...getInputProps({ "aria-describedby": describedBy, spellCheck: false })} />
        <button type="button" className="small" aria-label="Show the choices" tabIndex={-1} {...getToggleButtonProps()}>
          ▾
        </button>
      </div>
      <ul {...getMenuProps()} className="picker-menu" hidden={!isOpen}>
        {isOpen &&
          items.map((c, index) => (
            <li
              key={c.value}
              className={`${highlightedIndex === index ? "active" : ""}${c.value === value ? " current" : ""}`}
              {...getItemProps({ item: c, index })}
            >
              {c.label}
              {c.detail && <span className="hint"> · {c.detail}</span>}
            </li>
          ))}
        {isOpen && items.length === 0 && <li className="empty">Nothing matches “{query}”.</li>}
        {isOpen && found.length > items.length && (
          <li className="hint">{found.length - items.length} more: type to narrow the list.</li>
        )}
      </ul>
    </div>
  );
}

/**
 * A text input (or textarea) that keeps its own text while typing and calls `onCommit` on
 * Enter (inputs) or blur. `onCommit` answers an error message to show, or nothing.
 */
// Length: one field with its commit-on-Enter-or-blur states for input and textarea.
export function CommitField({
  id,
  label,
  value,
  onCommit,
  multiline = false,
  rows = 2,
  className,
  hint,
  ariaLabel,
}: {
  id: string;
  label?: string;
  value: string;
  onCommit: (text: string) => string | void;
  multiline?: boolean;
  rows?: number;
  className?: string;
  hint?: string;
  ariaLabel?: string;
}) {
  const [text, setText] = useState(value);
  const [error, setError] = useState("");
  const editing = useRef(false);
  useEffect(() => {
    if (!editing.current) setText(value);
  }, [value]);
  const commit = () => {
    editing.current = false;
    if (text === value) {
      setError("");
      return;
    }
    const problem = onCommit(text);
    setError(problem || "");
  };
  const common = {
    id,
    value: text,
    className,
    "aria-label": ariaLabel,
    "aria-invalid": error ? true : undefined,
    "aria-describedby": `${id}-error`,
    onChange: (e: { target: { value: string } }) => {
      editing.current = true;
      setText(e.target.value);
    },
    onBlur: commit,
  };
  return (
    <>
      {label && <label htmlFor={id}>{label}</label>}
      {multiline ? (
        <textarea {...common} rows={rows} />
      ) : (
        <input
          {...common}
          onKeyDown={(e) => {
            if (e.key === "Enter") {
              e.preventDefault();
              commit();
            }
          }}
        />
      )}
      {hint && <span className="hint">{hint}</span>}
      <span id={`${id}-error`} className="field-error" role={error ? "alert" : undefined}>
        {error}
      </span>
    </>
  );
}

/**
 * The expression editor: a combobox whose list offers the quantity names (and keywords) that
 * start with the word at the caret. ArrowDown/ArrowUp move, Enter or Tab accepts, Escape closes.
 * A parse error or an unknown quantity shows under the field with its column.
 */
// Length: one expression field: parse, suggest and commit states beside its markup.
export function ExprField({
  id,
  label,
  value,
  known,
  onChange,
  serverMessage,
}: {
  id: string;
  label: string;
  value: string;
  known: string[];
  onChange: (text: string) => void;
  serverMessage?: string;
}) {
  const listId = useId();
  const input = useRef<HTMLInputElement>(null);
  const [caret, setCaret] = useState<number | null>(null);
  const [active, setActive] = useState(0);
  const [closed, setClosed] = useState(true);
  const items = useMemo(
    () => (caret === null || closed ? [] : completions(value, caret, known).items),
    [value, caret, known, closed],
  );
  const error = useMemo(() => (value.trim() === "" ? null : checkExpr(value, known)), [value, known]);
  const open = items.length > 0;

  const accept = (word: string) => {
    const at = caret ?? value.length;
    const done = applyCompletion(value, at, word);
    pendingCaret.current = done.caret;
    setCaret(done.caret);
    setClosed(true);
    onChange(done.text);
  };
  // The caret goes after the completed word as soon as the new text is in the field.
  const pendingCaret = useRef<number | null>(null);
  useLayoutEffect(() => {
    const at = pendingCaret.current;
    if (at === null || !input.current) return;
    pendingCaret.current = null;
    input.current.setSelectionRange(at, at);
  }, [value]);
  const onKey = (e: KeyboardEvent<HTMLInputElement>) => {
    if (!open) return;
    if (e.key === "ArrowDown") setActive((a) => (a + 1) % items.length);
    else if (e.key === "ArrowUp") setActive((a) => (a - 1 + items.length) % items.length);
    else if (e.key === "Enter" || e.key === "Tab") accept(items[Math.min(active, items.length - 1)]!);
    else if (e.key === "Escape") setClosed(true);
    else return;
    e.preventDefault();
  };
  return (
    <div className="expr-field">
      <label htmlFor={id}>{label}</label>
      <input
        id={id}
        ref={input}
        className="code"
        role="combobox"
        autoComplete="off"
        spellCheck={false}
        aria-autocomplete="list"
        aria-expanded={open}
        aria-controls={listId}
        aria-activedescendant={open ? `${listId}-${active}` : undefined}
        aria-invalid={error ? true : undefined}
        aria-describedby={`${id}-error`}
        value={value}
        onChange={(e) => {
          onChange(e.target.value);
          setCaret(e.target.selectionStart);
          setActive(0);
          setClosed(false);
        }}
        onKeyDown={onKey}
        onBlur={() => setClosed(true)}
      />
      <ul id={listId} role="listbox" className="completions" hidden={!open} aria-label={`Completions for ${label}`}>
        {items.map((w, i) => (
          <li
            key={w}
            id={`${listId}-${i}`}
            role="option"
            aria-selected={i === active}
            className={i === active ? "active" : undefined}
            onMouseDown={(e) => {
              e.preventDefault();
              accept(w);
            }}
          >
            {w}
          </li>
        ))}
      </ul>
      <span id={`${id}-error`} className="field-error" data-testid={`${id}-error`}>
        {error ? `Column ${error.col}: ${error.message}` : serverMessage ?? ""}
      </span>
    </div>
  );
}
