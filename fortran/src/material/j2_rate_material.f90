!> The rate-dependent J2 member of the material family (schema name "j2_rate"): the J2 law of
!> j2_material (plane stress, linear combined hardening, radial return) with Cowper-Symonds rate
!> scaling of its yield radius, as LS-DYNA's MAT_003 with SRC and SRP (Cowper & Symonds 1957;
!> Jones, Structural Impact, ch. 8, whose mild steel has C = 40.4 1/s, P = 5):
!>
!>   sigma_y = (sigma_y0 + beta H eps_p) (1 + (rate / C)^(1/P))
!>
!> rate is each point's effective (von Mises) strain rate over the step, from its strain increment
!> (d1, d2, g12: engineering shear) and the step dt, the thickness strain taken from plastic
!> incompressibility d3 = -(d1 + d2):
!>
!>   rate = sqrt(2/3 (d1^2 + d2^2 + d3^2 + g12^2 / 2)) / dt
!>        = sqrt(4/3 (d1^2 + d2^2 + d1 d2) + g12^2 / 3) / dt
!>
!> (1 under uniaxial plastic flow at unit axial rate; g12 / sqrt(3) in pure shear). The rate is
!> the step's own, unfiltered; the member keeps no state of its own. Everything else (back stress
!> points, history, dissipated work) is j2_material's: the dissipated work reported is the
!> integral of the static yield radius, so the overstress's share of the plastic work stays in the
!> internal energy without being counted as plastic work (dissipated_work gets eps_p alone).
module j2_rate_material
  use paradyn_kinds, only: wp, ek
  use j2_material, only: j2_material_t
  use plane_stress_returns, only: j2_plane_stress_update_points
  use uniaxial_returns, only: j2_uniaxial_update_points, uniaxial_rate
  implicit none
  private
  public :: j2_rate_material_t

  type, extends(j2_material_t) :: j2_rate_material_t
    real(wp) :: rate_c = 1.0_wp   !< Cowper-Symonds C (1/s), > 0
    real(wp) :: rate_p = 1.0_wp   !< Cowper-Symonds P, > 0
  contains
    procedure :: update_points => j2_rate_update_points
    procedure :: update_uniaxial => j2_rate_update_uniaxial
  end type j2_rate_material_t

contains

  pure subroutine j2_rate_update_points(self, m, dt, stress, back, eps_p, state, dstrain)
    class(j2_rate_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek) :: scale(m), rate, inverse_c, exponent, inverse_dt
    integer :: i
    inverse_c = real(1.0_wp / self%rate_c, ek)
    exponent = real(1.0_wp / self%rate_p, ek)
    inverse_dt = merge(1.0_ek / dt, 0.0_ek, dt > 0.0_ek)   ! no step, no rate
    do i = 1, m
      rate = sqrt(max(4.0_ek / 3.0_ek * (dstrain(i, 1)**2 + dstrain(i, 2)**2 + dstrain(i, 1) * dstrain(i, 2)) &
                      + dstrain(i, 3)**2 / 3.0_ek, 0.0_ek)) * inverse_dt
      ! 0**x = 0 for x > 0: a point at rest keeps the static yield radius exactly
      scale(i) = 1.0_ek + (rate * inverse_c)**exponent
    end do
    call j2_plane_stress_update_points(m, stress, back, eps_p, dstrain, real(self%young, ek), &
                                       real(self%poisson, ek), real(self%yield_stress, ek), &
                                       real(self%tangent_modulus, ek), real(self%hardening_mixing, ek), &
                                       yield_scale=scale)
  end subroutine j2_rate_update_points

  !> The uniaxial return with the yield radius scaled by 1 + (rate / C)^(1/P), rate = |deps| / dt
  !> (the effective rate of uniaxial plastic flow, as update_points' rate).
  pure subroutine j2_rate_update_uniaxial(self, m, dt, stress, back, eps_p, state, dstrain)
    class(j2_rate_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:), back(:), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:)
    real(ek) :: scale(m)
    integer :: i
    do i = 1, m
      scale(i) = 1.0_ek + (uniaxial_rate(dstrain(i), dt) * real(1.0_wp / self%rate_c, ek))**real(1.0_wp / self%rate_p, ek)
    end do
    call j2_uniaxial_update_points(m, stress, back, eps_p, dstrain, real(self%young, ek), &
                                   real(self%yield_stress, ek), real(self%tangent_modulus, ek), &
                                   real(self%hardening_mixing, ek), scale)
  end subroutine j2_rate_update_uniaxial

end module j2_rate_material
