/** The Mission panel: the mission's id, title, description and target vehicle. */
import { VehiclePicker } from "./VehiclePicker";
import { type Orders } from "./graph";
import { updateMission } from "./model";
import { type EditOrders } from "./panels";

export function MissionPanel({ orders, editOrders }: { orders: Orders; editOrders: EditOrders }) {
  return (
    <fieldset className="panel-box">
      <legend>Mission</legend>
      <label htmlFor="mission-id">Mission id</label>
      <input id="mission-id" value={orders.id} readOnly aria-readonly="true" />
      <label htmlFor="mission-title">Mission title</label>
      <input
        id="mission-title"
        value={orders.title ?? ""}
        onChange={(e) => editOrders((o) => updateMission(o, { title: e.target.value }), "mission:title")}
      />
      <label htmlFor="mission-description">Mission description</label>
      <textarea
        id="mission-description"
        rows={3}
        value={orders.description ?? ""}
        onChange={(e) => editOrders((o) => updateMission(o, { description: e.target.value }), "mission:description")}
      />
      <VehiclePicker
        value={orders.vehicle ?? ""}
        carried={orders.vehicles ?? []}
        onChange={(vehicle) => editOrders((o) => updateMission(o, { vehicle }))}
      />
    </fieldset>
  );
}
