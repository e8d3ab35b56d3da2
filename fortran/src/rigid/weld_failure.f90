!> The failure of a weld (docs/theory.md, "Weld failure"): a rigid body of a few nodes lets them go
!> when the force its constraint carries reaches the failure surface of LS-DYNA's
!> *CONSTRAINED_SPOTWELD, (max(fn, 0) / SN)^N + (|fs| / SS)^M >= 1, or at its failure time. The
!> force is the one the constraint applies to one node of the weld (a two-node weld's N1): that
!> node's m dv / dt beyond its own forces, fn its part along the weld's normal (N1 -> N2, tension
!> > 0), fs the rest. Pure: the plumbing (rigid_body_effect) sums the force over the ranks. A weld
!> with a failure plastic strain (LS-DYNA EP, EPSF) also lets go when the largest effective plastic
!> strain of the shell integration points around its nodes reaches it (weld_strain_failed: a rigid
!> weld has no strain of its own, so its shells' is taken).
module weld_failure
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: weld_t, weld_make, weld_has_force_criterion, weld_criterion, weld_has_strain_criterion, &
            weld_strain_failed

  type :: weld_t
    real(wp) :: strength(2) = 0      !< SN, SS (N); 0: no failure in that mode
    real(wp) :: exponent(2) = 2      !< N, M
    real(wp) :: time = huge(1.0_wp)  !< the failure time (s)
    real(wp) :: normal(3) = 0        !< the unit normal at t = 0 in the body's axes (0: none)
    real(wp) :: plastic_strain = 0   !< the failure plastic strain of the shells at its nodes (0: none)
  end type weld_t

contains

  !> A weld from its deck row: strengths SN, SS, exponents N, M, failure time, normal (any length),
  !> failure plastic strain.
  pure function weld_make(strength, exponent, time, normal, plastic_strain) result(w)
    real(wp), intent(in) :: strength(2), exponent(2), time, normal(3), plastic_strain
    type(weld_t) :: w
    w%plastic_strain = plastic_strain
    w%strength = strength
    w%exponent = exponent
    w%time = time
    if (norm2(normal) > 0.0_wp) w%normal = normal / norm2(normal)
  end function weld_make

  !> Whether the weld can fail by its force (SN or SS given).
  pure logical function weld_has_force_criterion(w)
    type(weld_t), intent(in) :: w
    weld_has_force_criterion = any(w%strength > 0.0_wp)
  end function weld_has_force_criterion

  !> (max(fn, 0) / SN)^N + (|fs| / SS)^M for the force on the weld's node, its normal turned by
  !> rotation (the body's, from its axes at t = 0); a mode whose strength is 0 adds nothing. The
  !> weld fails where this is >= 1.
  pure real(wp) function weld_criterion(w, force, rotation) result(value)
    type(weld_t), intent(in) :: w
    real(wp), intent(in) :: force(3), rotation(3, 3)
    real(wp) :: n(3), fn, fs
    n = matmul(rotation, w%normal)
    fn = dot_product(force, n)
    fs = norm2(force - fn * n)
    value = 0.0_wp
    if (w%strength(1) > 0.0_wp) value = value + (max(fn, 0.0_wp) / w%strength(1))**w%exponent(1)
    if (w%strength(2) > 0.0_wp) value = value + (fs / w%strength(2))**w%exponent(2)
  end function weld_criterion

  !> Whether the weld can fail by the plastic strain of its shells (EP given).
  pure logical function weld_has_strain_criterion(w)
    type(weld_t), intent(in) :: w
    weld_has_strain_criterion = w%plastic_strain > 0.0_wp
  end function weld_has_strain_criterion

  !> Whether eps_p, the largest effective plastic strain of the shell integration points around
  !> the weld's nodes, has reached its failure plastic strain.
  pure logical function weld_strain_failed(w, eps_p)
    type(weld_t), intent(in) :: w
    real(wp), intent(in) :: eps_p
    weld_strain_failed = weld_has_strain_criterion(w) .and. eps_p >= w%plastic_strain
  end function weld_strain_failed

end module weld_failure
