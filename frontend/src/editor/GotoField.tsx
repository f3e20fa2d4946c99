/**
 * The toolbar's "Go to node" field: a combobox (downshift) whose suggestions are the node ids
 * starting with what is typed. Enter with an exact id typed goes to that node even while the
 * list is open and another suggestion is highlighted (G1 typed, the pointer resting on G10):
 * the browser's own suggestion list (a datalist) took that Enter now and then and went nowhere.
 */
import { useCombobox } from "downshift";
import { type KeyboardEvent, useMemo, useState } from "react";

const SHOWN = 12;

export function GotoField({ ids, onGo }: { ids: string[]; onGo: (id: string) => void }) {
  const [text, setText] = useState("");
  const typed = text.trim();
  const items = useMemo(() => ids.filter((id) => id.toLowerCase().startsWith(typed.toLowerCase())).slice(0, SHOWN), [ids, typed]);
  const { isOpen, highlightedIndex, closeMenu, getLabelProps, getInputProps, getMenuProps, getItemProps } = useCombobox<string>({
    items,
    inputId: "goto-node",
    labelId: "goto-node-label",
    menuId: "goto-node-menu",
    inputValue: text,
    selectedItem: null,
    onInputValueChange: ({ inputValue }) => setText(inputValue ?? ""),
    onSelectedItemChange: ({ selectedItem }) => {
      if (selectedItem) onGo(selectedItem);
    },
  });
  const onKeyDown = (event: KeyboardEvent<HTMLInputElement>) => {
    if (event.key !== "Enter" || !ids.includes(typed)) return;
    // The exact id typed wins over the highlighted suggestion.
    (event.nativeEvent as { preventDownshiftDefault?: boolean }).preventDownshiftDefault = true;
    event.preventDefault();
    closeMenu();
    onGo(typed);
  };
  return (
    <form
      className="goto"
      onSubmit={(e) => {
        e.preventDefault();
        onGo(typed);
      }}
    >
      <label {...getLabelProps()}>Go to node</label>
      <span className="goto-field">
        <input {...getInputProps({ onKeyDown, size: 6, spellCheck: false })} />
        <ul {...getMenuProps({ "aria-labelledby": undefined, "aria-label": "Node ids starting with the text typed" })} className="picker-menu goto-menu" hidden={!isOpen || items.length === 0}>
          {isOpen &&
            items.map((id, index) => (
              <li key={id} className={highlightedIndex === index ? "active" : ""} {...getItemProps({ item: id, index })}>
                {id}
              </li>
            ))}
        </ul>
      </span>
      <button type="submit">Go</button>
    </form>
  );
}
