!> The linear elastic member of the material family (schema name "elastic").
module elastic_material
  use paradyn_kinds, only: wp, ek
  use material_model, only: material_t
  use plane_stress_returns, only: elastic_plane_stress_update_points
  implicit none
  private
  public :: elastic_material_t

  type, extends(material_t) :: elastic_material_t
  contains
    procedure :: update_points => elastic_update_points
    procedure :: update_uniaxial => elastic_update_uniaxial
    procedure :: back_stress_points => elastic_back_points
    procedure :: has_history => elastic_has_history
    procedure :: dissipated_work => elastic_dissipated_work
  end type elastic_material_t

contains

  pure subroutine elastic_update_points(self, m, dt, stress, back, eps_p, state, dstrain)
    class(elastic_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    call elastic_plane_stress_update_points(m, stress, dstrain, real(self%young, ek), real(self%poisson, ek))
  end subroutine elastic_update_points

  !> sigma += E deps (a bar's uniaxial stress: no lateral stress, so no Poisson coupling).
  pure subroutine elastic_update_uniaxial(self, m, dt, stress, back, eps_p, state, dstrain)
    class(elastic_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:), back(:), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:)
    stress(1:m) = stress(1:m) + real(self%young, ek) * dstrain(1:m)
  end subroutine elastic_update_uniaxial

  pure integer function elastic_back_points(self, nip) result(points)
    class(elastic_material_t), intent(in) :: self
    integer, intent(in) :: nip
    points = 0
  end function elastic_back_points

  pure logical function elastic_has_history(self) result(changes)
    class(elastic_material_t), intent(in) :: self
    changes = .false.
  end function elastic_has_history

  pure subroutine elastic_dissipated_work(self, eps_p, work)
    class(elastic_material_t), intent(in) :: self
    real(wp), intent(in) :: eps_p(:, :)
    real(wp), intent(out) :: work(:, :)
    work = 0.0_wp
  end subroutine elastic_dissipated_work

end module elastic_material
