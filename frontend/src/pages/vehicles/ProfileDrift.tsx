/**
 * "Needs re-approval": the registry's current profile of the orders' target vehicle differs
 * from the profile these orders carry (the one the checks and the signature covered). The
 * signature stays valid for what it covered; the notice says what a new approval would change.
 */
import type { Schema } from "../../api/client";
import { type RegistryProfile, useRegistryVersions } from "../../api/vehicles";
import { ProfileChanges } from "./ProfileChanges";
import { profileDiff } from "./profileDiff";

function targetProfile(orders: Schema<"Orders">): RegistryProfile | undefined {
  const carried = orders.vehicles ?? [];
  const id = orders.vehicle;
  if (id) return carried.find((v) => v.id === id);
  return carried.length === 1 ? carried[0] : undefined;
}

export function ProfileDrift({ orders, approved }: { orders: Schema<"Orders">; approved: boolean }) {
  const signed = targetProfile(orders);
  const id = signed?.id ?? "";
  const { data } = useRegistryVersions(id);
  const latest = data?.[0];
  if (!signed || !latest) return null;
  const changes = profileDiff(signed, latest.profile);
  if (changes.length === 0) return null;
  return (
    <section className="message warning" aria-labelledby="profile-drift-title" data-testid="profile-drift">
      <h2 id="profile-drift-title">{approved ? "Needs re-approval" : "Vehicle profile changed in the registry"}</h2>
      <p>
        The registry&apos;s profile of vehicle <code>{id}</code> (version {latest.number}) differs from the profile in these
        orders.{" "}
        {approved
          ? "The signature stays valid for the profile it covered; the vehicle as registered now needs a new version and a new approval."
          : "These orders were checked against the profile they carry; a new version takes the registry's profile only if the draft drops its own."}
      </p>
      <ProfileChanges changes={changes} testId="profile-drift-diff" />
    </section>
  );
}
