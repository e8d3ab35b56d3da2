!> The uniaxial (1-D) returns of the material family's plastic members, for a bar's axial stress
!> (element/truss_element): the same yield stress and hardening as their plane-stress returns,
!> with the lateral stresses zero, so the return is scalar and closed-form on a line of the
!> hardening law (Simo & Hughes, Computational Inelasticity, 1998, sec. 1.4: the 1-D return
!> mapping with combined linear hardening). Pure kernels, no state.
module uniaxial_returns
  use paradyn_kinds, only: ek
  implicit none
  private
  public :: j2_uniaxial_update_points, uniaxial_rate

contains

  !> Combined linear hardening, H = E Et / (E - Et), isotropic part beta H, kinematic (1 - beta) H,
  !> the yield radius scaled by yield_scale (a rate factor, 1 without):
  !>   xi = sigma + E deps - alpha,  k = scale (sigma_y0 + beta H eps_p),
  !>   f = |xi| - k > 0:  dlambda = f / (E + (1 - beta) H + scale beta H),
  !>   sigma = sigma_trial - E dlambda sign(xi), alpha += (1 - beta) H dlambda sign(xi), eps_p += dlambda.
  !> back(1:m) is updated only where kinematic hardening acts (size(back) = 0: no back stress kept).
  pure subroutine j2_uniaxial_update_points(m, stress, back, eps_p, dstrain, young, yield0, tangent, beta, &
                                            yield_scale)
    integer, intent(in) :: m
    real(ek), intent(inout) :: stress(:), back(:), eps_p(:)
    real(ek), intent(in) :: dstrain(:), young, yield0, tangent, beta, yield_scale(:)
    real(ek) :: h, h_kin, h_iso, xi, alpha, f, dlambda, direction
    integer :: i
    h = young * tangent / (young - tangent)
    h_iso = beta * h
    h_kin = (1.0_ek - beta) * h
    do i = 1, m
      stress(i) = stress(i) + young * dstrain(i)
      alpha = 0.0_ek
      if (size(back) > 0) alpha = back(i)
      xi = stress(i) - alpha
      f = abs(xi) - yield_scale(i) * (yield0 + h_iso * eps_p(i))
      if (f <= 0.0_ek) cycle
      direction = sign(1.0_ek, xi)
      dlambda = f / (young + h_kin + yield_scale(i) * h_iso)
      stress(i) = stress(i) - young * dlambda * direction
      if (size(back) > 0) back(i) = alpha + h_kin * dlambda * direction
      eps_p(i) = eps_p(i) + dlambda
    end do
  end subroutine j2_uniaxial_update_points

  !> The effective strain rate of uniaxial flow over a step: |deps| / dt (0 without a step); the
  !> plane-stress members' effective rate of the same flow (d2 = -d1 / 2) is this one.
  pure real(ek) function uniaxial_rate(deps, dt) result(rate)
    real(ek), intent(in) :: deps, dt
    rate = 0.0_ek
    if (dt > 0.0_ek) rate = abs(deps) / dt
  end function uniaxial_rate

end module uniaxial_returns
