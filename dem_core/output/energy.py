"""The model's energy account, J/m (per metre of thickness, plane strain).

    W_external = E_kinetic + E_strain + D_fracture + D_friction + D_damping      (+ balance)

- W_external: the work of gravity on every block (minus its potential relative to the start,
  ``monitor.gravity_energy``) plus the work put in through prescribed velocity components,
  -f v_bc dt summed over the steps (``step.integration``; f the force of the contacts and
  gravity on the block held at v_bc).
- E_kinetic: 1/2 m v^2 + 1/2 I omega^2 of the free velocity components, with the inertial
  masses the integration uses (a prescribed component's motion is the boundary's).
- E_strain: the contact springs' elastic energy (``monitor.strain_energy``).
- D_fracture: the work spent on softening bonds (``contact.softening``), kept per contact
  (``Contacts.work_fracture``). A brittle bond dissipates nothing when it fails: its spring's
  energy goes to motion and then to damping.
- D_friction: plastic slip against friction (``Contacts.work_friction``).
- D_damping: what local damping took out over each kick and what the kinetic-damping stops
  removed (``BlockState.work``).

Contacts dropped by a search or an excavation take their dissipation with them; the model
keeps it in ``Model.energy_bank`` (``bank_dropped``). The account starts when the model is
built (contacts stress-free, blocks at rest) or at ``Model.reset_energy`` (the stored energy
then is its origin, so a scene with an initial stress starts at a zero balance). An excavation
(``Model.remove``) starts it anew: the removed blocks take their energy out of the model.

Not in the account yet (listed under "missing" when the scene has them): applied loads,
servos, water pressures, cables and liners, deformable blocks' zones. The balance then does
not close by their work, and the account says so.
"""
from __future__ import annotations

import numpy as np

from .monitor import gravity_energy, strain_energy
from ..step.relaxation import free_kinetic_energy

__all__ = ["energy_account", "bank_dropped", "reset_origin", "BANK"]

# Model.energy_bank entries: dissipation of contacts no longer in the model, and the origin
BANK = ("fracture", "friction", "strain_origin", "gravity_origin", "boundary_origin",
        "damping_origin")


def bank_dropped(bank, before, after) -> None:
    """Add to ``bank`` the dissipation of contacts that are in ``before`` and not in
    ``after`` (the surviving contacts keep theirs)."""
    for j, name in enumerate(("work_fracture", "work_friction")):
        bank[j] += float(before.live(name).sum()) - float(after.live(name).sum())


def missing_terms(model) -> list:
    """The scene's energy sources the account does not hold yet (module docstring)."""
    out = []
    if np.any(model.load != 0.0):
        out.append("applied loads")
    if model.servo_groups:
        out.append("servos")
    if model.water is not None:
        out.append("water")
    if model.cables.node_pos.shape[0] or model.liners.node_pos.shape[0]:
        out.append("support")
    if model.deformable_blocks.any():
        out.append("deformable zones")
    return out


def energy_account(model) -> dict:
    """The terms of the account (module docstring), J/m, with "balance" = W_external minus
    the rest, "missing" (what the account does not hold for this scene) and "closure", the
    balance over the largest term (0 for an account with nothing in it yet)."""
    w, s, p = model.world(), model.state, model.props
    bank = model.energy_bank
    active = p.active > 0
    boundary = float(s.work[active, 0].sum()) - bank[4]
    damping = float(s.work[active, 1].sum()) - bank[5]
    out = {
        "external": boundary - (gravity_energy(w, model.gravity) - bank[3]),
        "boundary": boundary,
        "kinetic": free_kinetic_energy(s, p),
        "strain": strain_energy(model.contacts) - bank[2],
        "fracture": float(model.contacts.live("work_fracture").sum()) + bank[0],
        "friction": float(model.contacts.live("work_friction").sum()) + bank[1],
        "damping": damping,
    }
    out["balance"] = out["external"] - sum(out[k] for k in ("kinetic", "strain", "fracture",
                                                            "friction", "damping"))
    scale = max(abs(v) for k, v in out.items() if k != "balance")
    out["closure"] = abs(out["balance"]) / scale if scale > 0.0 else 0.0
    out["missing"] = missing_terms(model)
    return out


def reset_origin(model) -> None:
    """Start the account now: every term reads 0 and the stored energy is its origin."""
    s, a = model.state, model.props.active > 0
    bank = model.energy_bank
    bank[0] = -float(model.contacts.live("work_fracture").sum())
    bank[1] = -float(model.contacts.live("work_friction").sum())
    bank[2] = strain_energy(model.contacts)
    bank[3] = gravity_energy(model.world(), model.gravity)
    bank[4] = float(s.work[a, 0].sum())
    bank[5] = float(s.work[a, 1].sum())
