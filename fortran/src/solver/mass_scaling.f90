!> Mass scaling to a target step, at set-up (as LS-DYNA's negative DT2MS or Radioss /DT/NODA/CST:
!> mass is added only where an element would set a smaller step). An element whose stable step
!> times the safety factor, safety L / c, is below /control mass_scaling_step gets its density
!> raised by (target / (safety L / c))^2, so that its step equals the target (dt ~ sqrt(rho));
!> the others keep theirs. Each rank computes the factors of the elements it holds (model_deck's
!> layout); the sums over the model (the mass, the added mass per part) are taken in element order
!> over the ranks (parallel/ordered_sums), so every rank gets the same sums whatever the layout.
!> Without a target every factor is 1 and the step is the smallest element step of the initial mesh.
module mass_scaling
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, node_row
  use shell_section, only: shell_properties_t, local_frame
  use shell_measures, only: blt_stable_time_step, triangle_stable_time_step
  use truss_element, only: truss_stable_time_step, truss_length
  implicit none
  private
  public :: mass_scaling_t, mass_scaling_setup, mass_scaling_message

  type :: mass_scaling_t
    real(wp) :: target = 0          !< /control mass_scaling_step (s), 0 = off
    real(wp) :: limit = 0           !< /control mass_scaling_limit (fraction of the model's mass)
    real(wp), allocatable :: step_scale(:)   !< per held element (deck%element_ids): its step's factor, sqrt
                                             !< of its density's
    real(wp), allocatable :: element_mass(:), element_added(:)   !< per held element: its mass, its added mass
    real(wp), allocatable :: added_part(:)   !< added mass per part (kg), over the model once summed
    real(wp) :: added = 0           !< added mass in all (kg)
    real(wp) :: model_mass = 0      !< the model's mass before scaling (kg)
    real(wp) :: dt_element_min = 0  !< the smallest element step after scaling, no safety factor (s)
    !> the smallest step of a rigid part's elements as if elastic: the step of a model of rigid bodies alone
    real(wp) :: dt_rigid_min = 0
    integer :: scaled = 0           !< elements whose density was raised
  end type mass_scaling_t

contains

  !> The factors, masses and added masses of the held elements at their initial positions, and
  !> their smallest step and scaled count (this rank's: the totals come from ordered_sums).
  subroutine mass_scaling_setup(ms, deck, props)
    type(mass_scaling_t), intent(out) :: ms
    type(deck_t), intent(in) :: deck
    type(shell_properties_t), intent(in) :: props(:)
    real(wp) :: x(1, 3, 4), dt(1), e(3, 3), xl(4), yl(4), area, mass, wanted
    integer :: k, p, j
    ms%target = deck%mass_scaling_step
    ms%limit = deck%mass_scaling_limit
    allocate (ms%step_scale(size(deck%element_ids)), source=1.0_wp)
    allocate (ms%element_mass(size(deck%element_ids)), ms%element_added(size(deck%element_ids)), source=0.0_wp)
    allocate (ms%added_part(deck%n_parts), source=0.0_wp)
    ms%dt_element_min = huge(1.0_wp)
    ms%dt_rigid_min = huge(1.0_wp)
    do k = 1, size(deck%element_ids)
      p = deck%element_part(k)
      x(1, :, :) = deck%coordinates(:, [(node_row(deck, deck%connectivity(j, k)), j = 1, 4)])
      if (props(p)%truss) then
        call truss_stable_time_step(1, x, props(p), dt)
      else if (deck%connectivity(3, k) == deck%connectivity(4, k)) then
        call triangle_stable_time_step(1, x, props(p), dt)
      else
        call blt_stable_time_step(1, x, props(p), dt)
      end if
      if (props(p)%truss) then
        mass = props(p)%density * props(p)%area * truss_length(x(1, :, 1:2))
      else
        call local_frame(x(1, :, :), e, xl, yl, area)   ! a triangle's area too (its fourth corner is its third)
        mass = merge(0.0_wp, props(p)%density * props(p)%thickness * abs(area), props(p)%surface_only)
      end if
      ms%element_mass(k) = mass
      if (props(p)%rigid) then   ! a rigid body's element sets no step (unless all are rigid), is not scaled
        ms%dt_rigid_min = min(ms%dt_rigid_min, dt(1))
        cycle
      end if
      wanted = ms%target / deck%time_step_safety   ! the element step that gives the target
      if (ms%target > 0.0_wp .and. dt(1) < wanted) then
        ms%step_scale(k) = wanted / dt(1)
        ms%element_added(k) = (ms%step_scale(k)**2 - 1.0_wp) * mass
        ms%scaled = ms%scaled + 1
        dt(1) = dt(1) * ms%step_scale(k)
      end if
      ms%dt_element_min = min(ms%dt_element_min, dt(1))
    end do
  end subroutine mass_scaling_setup

  !> '' when the added mass is within the limit, else the message that refuses the run.
  function mass_scaling_message(ms) result(message)
    type(mass_scaling_t), intent(in) :: ms
    character(len=:), allocatable :: message
    character(len=400) :: text
    message = ''
    if (ms%target <= 0.0_wp .or. ms%added <= ms%limit * ms%model_mass) return
    write (text, '(a,es10.3,a,es10.3,a,i0,a,es10.3,a,es10.3,a)') 'mass scaling to /control mass_scaling_step = ', &
      ms%target, ' s adds ', ms%added, ' kg to ', ms%scaled, ' element(s), a fraction ', &
      ms%added / ms%model_mass, ' of the model''s mass, over /control mass_scaling_limit = ', ms%limit, &
      '; give a smaller mass_scaling_step, a larger mass_scaling_limit, or coarsen the small elements'
    message = trim(text)
  end function mass_scaling_message

end module mass_scaling
