!> The J2 plasticity member of the material family (schema name "j2_plasticity"): plane stress,
!> linear combined isotropic/kinematic hardening, radial return (plane_stress_returns).
module j2_material
  use paradyn_kinds, only: wp, ek
  use material_model, only: material_t
  use plane_stress_returns, only: j2_plane_stress_update_points, j2_kinematic_modulus
  use uniaxial_returns, only: j2_uniaxial_update_points
  implicit none
  private
  public :: j2_material_t

  type, extends(material_t) :: j2_material_t
    real(wp) :: yield_stress = 0.0_wp       !< initial yield stress (Pa)
    real(wp) :: tangent_modulus = 0.0_wp    !< plastic tangent modulus Et < E (Pa)
    real(wp) :: hardening_mixing = 1.0_wp   !< beta: 1 isotropic, 0 kinematic
  contains
    procedure :: update_points => j2_update_points
    procedure :: update_uniaxial => j2_update_uniaxial
    procedure :: back_stress_points => j2_back_points
    procedure :: has_history => j2_has_history
    procedure :: dissipated_work => j2_dissipated_work
  end type j2_material_t

contains

  pure subroutine j2_update_points(self, m, dt, stress, back, eps_p, state, dstrain)
    class(j2_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    call j2_plane_stress_update_points(m, stress, back, eps_p, dstrain, real(self%young, ek), &
                                       real(self%poisson, ek), real(self%yield_stress, ek), &
                                       real(self%tangent_modulus, ek), real(self%hardening_mixing, ek))
  end subroutine j2_update_points

  !> The uniaxial return of the same law (uniaxial_returns), no rate scaling.
  pure subroutine j2_update_uniaxial(self, m, dt, stress, back, eps_p, state, dstrain)
    class(j2_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:), back(:), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:)
    real(ek) :: scale(m)
    scale = 1.0_ek
    call j2_uniaxial_update_points(m, stress, back, eps_p, dstrain, real(self%young, ek), &
                                   real(self%yield_stress, ek), real(self%tangent_modulus, ek), &
                                   real(self%hardening_mixing, ek), scale)
  end subroutine j2_update_uniaxial

  !> Every point with kinematic hardening; none for perfect plasticity or purely isotropic
  !> hardening, where the back stress stays zero (not storing it saves over a quarter of the
  !> element state's memory traffic).
  pure integer function j2_back_points(self, nip) result(points)
    class(j2_material_t), intent(in) :: self
    integer, intent(in) :: nip
    points = 0
    if (j2_kinematic_modulus(self%young, self%tangent_modulus, self%hardening_mixing) /= 0.0_wp) points = nip
  end function j2_back_points

  pure logical function j2_has_history(self) result(changes)
    class(j2_material_t), intent(in) :: self
    changes = .true.
  end function j2_has_history

  !> The work of the stress relative to the back stress, integral of the yield radius
  !> sigma_y0 + beta H eps_p over eps_p: exact on any path for this law (the back stress's share,
  !> stored and recoverable, is not dissipated).
  pure subroutine j2_dissipated_work(self, eps_p, work)
    class(j2_material_t), intent(in) :: self
    real(wp), intent(in) :: eps_p(:, :)
    real(wp), intent(out) :: work(:, :)
    real(wp) :: h_iso
    h_iso = self%hardening_mixing * self%young * self%tangent_modulus / (self%young - self%tangent_modulus)
    work = self%yield_stress * eps_p + 0.5_wp * h_iso * eps_p**2
  end subroutine j2_dissipated_work

end module j2_material
