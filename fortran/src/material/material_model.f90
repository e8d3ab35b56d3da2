!> The material family: an abstract plane-stress law that updates the stresses of a batch of
!> through-thickness points at once (one dispatch per batch, so the members' loops vectorise), and
!> says how much state per point it keeps. Members: elastic_material (elastic), j2_material
!> (J2 plasticity with combined hardening), j2_rate_material (with Cowper-Symonds rates),
!> piecewise_linear_material (isotropic hardening along a curve, LS-DYNA MAT_024; one state word
!> per point); material_factory makes one from its schema name.
!> Each member has a uniaxial form too (update_uniaxial: a truss's axial stress, the same data).
!> A member gets the step (a rate law's strain rate is dstrain / dt), may keep state_width()
!> words of its own per point (stored, exchanged and checkpointed by the element state), and
!> may bound the step through the wave speed it reports.
module material_model
  use paradyn_kinds, only: wp, ek
  implicit none
  private
  public :: material_t, max_state_words

  integer, parameter :: max_state_words = 8   !< the most words of state per point a member may keep

  type, abstract :: material_t
    real(wp) :: young = 0.0_wp     !< Young's modulus (Pa)
    real(wp) :: poisson = 0.0_wp   !< Poisson's ratio
  contains
    !> stress(1:m, 1:3) += the law's response to dstrain(1:m, 1:3) (engineering shear), updating
    !> the back stress and plastic strain of points that store them; in the element kernel's kind
    !> ek (single in the mixed engine), the law's constants rounded to it
    procedure(update_points_interface), deferred :: update_points
    !> The law's uniaxial form (a truss's axial stress, element/truss_element): stress(1:m) += the
    !> response to the axial strain increments dstrain(1:m), with the same yield and hardening
    !> data; back(1:m) the axial back stress, eps_p and state as update_points'
    procedure(update_uniaxial_interface), deferred :: update_uniaxial
    !> Through-thickness points that store a back stress, of nip (0 where it stays zero)
    procedure(back_points_interface), deferred :: back_stress_points
    !> Whether the law changes the back stress or the plastic strain (else they are not written)
    procedure(history_interface), deferred :: has_history
    !> work(i, k): plastic work dissipated per unit volume at the points with equivalent plastic
    !> strains eps_p(i, k); a batch per call, as update_points (no temporaries per element)
    procedure(dissipation_interface), deferred :: dissipated_work
    !> Words of the member's own state per through-thickness point (0: none, the default)
    procedure :: state_width => no_state
    !> The dilatational wave speed that sets the stable step L / c at density rho (default: the
    !> plate wave speed sqrt(E / (rho (1 - nu^2)))); a stiffening member returns a larger one
    procedure :: wave_speed => plate_wave_speed
  end type material_t

  abstract interface
    !> dt: the step over which dstrain accrues; state(1:m, 1:state_width()): the member's own
    pure subroutine update_points_interface(self, m, dt, stress, back, eps_p, state, dstrain)
      import :: material_t, ek
      class(material_t), intent(in) :: self
      integer, intent(in) :: m
      real(ek), intent(in) :: dt
      real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
      real(ek), intent(in), contiguous :: dstrain(:, :)
    end subroutine update_points_interface

    pure subroutine update_uniaxial_interface(self, m, dt, stress, back, eps_p, state, dstrain)
      import :: material_t, ek
      class(material_t), intent(in) :: self
      integer, intent(in) :: m
      real(ek), intent(in) :: dt
      real(ek), intent(inout), contiguous :: stress(:), back(:), eps_p(:), state(:, :)
      real(ek), intent(in), contiguous :: dstrain(:)
    end subroutine update_uniaxial_interface

    pure integer function back_points_interface(self, nip) result(points)
      import :: material_t
      class(material_t), intent(in) :: self
      integer, intent(in) :: nip
    end function back_points_interface

    pure logical function history_interface(self) result(changes)
      import :: material_t
      class(material_t), intent(in) :: self
    end function history_interface

    pure subroutine dissipation_interface(self, eps_p, work)
      import :: material_t, wp
      class(material_t), intent(in) :: self
      real(wp), intent(in) :: eps_p(:, :)
      real(wp), intent(out) :: work(:, :)
    end subroutine dissipation_interface
  end interface

contains

  pure integer function no_state(self) result(width)
    class(material_t), intent(in) :: self
    width = 0
  end function no_state

  pure real(wp) function plate_wave_speed(self, density) result(c)
    class(material_t), intent(in) :: self
    real(wp), intent(in) :: density
    c = sqrt(self%young / (density * (1.0_wp - self%poisson**2)))
  end function plate_wave_speed

end module material_model
