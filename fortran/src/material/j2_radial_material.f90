!> The J2 member with the radial return without the plane-stress iteration (schema name
!> "j2_radial"; plane_stress_returns' j2_radial_update_points): the same law and data as
!> j2_material, the cheaper return of explicit codes, as a model choice (docs/theory.md).
module j2_radial_material
  use paradyn_kinds, only: ek
  use j2_material, only: j2_material_t
  use plane_stress_returns, only: j2_radial_update_points
  implicit none
  private
  public :: j2_radial_material_t

  type, extends(j2_material_t) :: j2_radial_material_t
  contains
    procedure :: update_points => j2_radial_points
  end type j2_radial_material_t

contains

  pure subroutine j2_radial_points(self, m, dt, stress, back, eps_p, state, dstrain)
    class(j2_radial_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    call j2_radial_update_points(m, stress, back, eps_p, dstrain, real(self%young, ek), real(self%poisson, ek), &
                                 real(self%yield_stress, ek), real(self%tangent_modulus, ek), &
                                 real(self%hardening_mixing, ek))
  end subroutine j2_radial_points

end module j2_radial_material
