!> The state of the shell elements of one rank, group by group: each group (one part, at most
!> group_size elements) owns arrays shaped for the element kernel, element index first, so the
!> kernel gets whole arrays instead of offsets into pools. Also the element energies, and the rows
!> by which a checkpoint stores the state element by element.
module element_state
  use paradyn_kinds, only: wp, ek
  use domain_decomposition, only: domain_t
  use shell_section, only: shell_properties_t, stress_components, hourglass_components, in_plane_points
  implicit none
  private
  public :: group_state_t, element_state_t, element_state_setup, element_row_width, element_rows_pack, &
            element_rows_unpack

  !> The state the element kernel updates, in its kind ek (core/kinds.f90): single in the mixed
  !> engine, where the kernel adds each step's increment in single anyway (docs/theory.md, "Precision").
  type :: group_state_t
    real(ek), allocatable :: stress(:, :, :)   !< (elements, stress_components, points), local frame
    real(ek), allocatable :: back(:, :, :)     !< (elements, 3, points), or no points without kinematic hardening
    real(ek), allocatable :: eps_p(:, :)       !< (elements, points) effective plastic strain
    real(ek), allocatable :: hourglass(:, :)   !< (elements, hourglass_components) resultants
    real(ek), allocatable :: state(:, :, :)    !< (elements, words, points): the material member's own
    !> (elements) the current thickness of a part with thickness_update; no elements otherwise
    real(ek), allocatable :: thickness(:)
  end type group_state_t

  type :: element_state_t
    type(group_state_t), allocatable :: groups(:)
    real(wp), allocatable :: e_internal(:), e_hourglass(:)   !< per local element (J)
    real(wp), allocatable :: dt_element(:)   !< per local element: L / c at the last forces, unscaled density (s)
    real(wp), allocatable :: step_scale(:)   !< per local element: its step's factor from mass scaling (1: none)
    integer :: inverted = 0   !< elements found inside out so far
    integer :: max_state = 0  !< the most words of material state per point of any part (checkpoint rows)
    !> 1 when some part updates its thickness (a word per checkpoint row), else 0
    integer :: thickness_words = 0
  end type element_state_t

contains

  subroutine element_state_setup(es, dom, props)
    type(element_state_t), intent(out) :: es
    type(domain_t), intent(in) :: dom
    type(shell_properties_t), intent(in) :: props(:)
    integer :: g, n, nip, p, part
    es%max_state = maxval([(props(p)%material%state_width(), p = 1, size(props))])
    es%thickness_words = merge(1, 0, any([(props(p)%thickness_update, p = 1, size(props))]))
    allocate (es%groups(dom%n_groups))
    do g = 1, dom%n_groups
      n = dom%group_count(g)
      part = dom%group_part(g)
      ! the stored points: through-thickness x in-plane (4 for a fully integrated part's quadrilaterals)
      nip = props(part)%integration_points * in_plane_points(props(part), dom%group_triangle(g))
      allocate (es%groups(g)%stress(n, stress_components, nip), source=0.0_ek)
      allocate (es%groups(g)%back(n, 3, props(part)%material%back_stress_points(nip)), source=0.0_ek)
      allocate (es%groups(g)%eps_p(n, nip), es%groups(g)%hourglass(n, hourglass_components), source=0.0_ek)
      allocate (es%groups(g)%state(n, props(part)%material%state_width(), nip), source=0.0_ek)
      allocate (es%groups(g)%thickness(merge(n, 0, props(part)%thickness_update)), &
                source=real(props(part)%thickness, ek))
    end do
    allocate (es%e_internal(dom%n_elements), es%e_hourglass(dom%n_elements), source=0.0_wp)
    allocate (es%dt_element(dom%n_elements), source=huge(1.0_wp))
    allocate (es%step_scale(dom%n_elements), source=1.0_wp)
  end subroutine element_state_setup

  !> Doubles per element row: stress, back stress and plastic strain at the most points any part
  !> uses, the hourglass resultants, the two energies, then the material state (max_state words
  !> at each point; none for the elastic and J2 members, so their rows keep their width), then
  !> thickness_words (1: the current thickness, when some part updates it; 0: none).
  pure integer function element_row_width(max_points, max_state, thickness_words) result(width)
    integer, intent(in) :: max_points, max_state, thickness_words
    width = (stress_components + 3 + 1) * max_points + hourglass_components + 2 + max_state * max_points + &
            thickness_words
  end function element_row_width

  !> Element state by element (checkpoints). A row holds the stress (components x points), back
  !> stress and plastic strain, each at the width of the most points any part uses, then the
  !> hourglass resultants, the internal and hourglass energies and the material state. A part
  !> without kinematic hardening stores no back stress (zeros in the rows).
  subroutine element_rows_pack(es, dom, rows)
    type(element_state_t), intent(in) :: es
    type(domain_t), intent(in) :: dom
    real(wp), intent(out) :: rows(:, :)
    integer :: g, i, e, o(5)
    rows = 0.0_wp
    o = row_offsets(size(rows, 1) - es%thickness_words, es%max_state)
    do g = 1, dom%n_groups
      associate (gs => es%groups(g))
        do i = 1, dom%group_count(g)
          e = dom%group_first(g) + i - 1
          rows(o(1) + 1:o(1) + size(gs%stress(i, :, :)), e) = reshape(gs%stress(i, :, :), [size(gs%stress(i, :, :))])
          rows(o(2) + 1:o(2) + size(gs%back(i, :, :)), e) = reshape(gs%back(i, :, :), [size(gs%back(i, :, :))])
          rows(o(3) + 1:o(3) + size(gs%eps_p, 2), e) = gs%eps_p(i, :)
          rows(o(4) + 1:o(4) + hourglass_components, e) = gs%hourglass(i, :)
          rows(o(5) + 1:o(5) + size(gs%state(i, :, :)), e) = reshape(gs%state(i, :, :), [size(gs%state(i, :, :))])
          if (size(gs%thickness) > 0) rows(size(rows, 1), e) = gs%thickness(i)
        end do
      end associate
    end do
    rows(o(4) + hourglass_components + 1, :) = es%e_internal
    rows(o(4) + hourglass_components + 2, :) = es%e_hourglass
  end subroutine element_rows_pack

  subroutine element_rows_unpack(es, dom, rows)
    type(element_state_t), intent(inout) :: es
    type(domain_t), intent(in) :: dom
    real(wp), intent(in) :: rows(:, :)
    integer :: g, i, e, o(5)
    o = row_offsets(size(rows, 1) - es%thickness_words, es%max_state)
    do g = 1, dom%n_groups
      associate (gs => es%groups(g))
        do i = 1, dom%group_count(g)
          e = dom%group_first(g) + i - 1
          gs%stress(i, :, :) = reshape(real(rows(o(1) + 1:o(1) + size(gs%stress(i, :, :)), e), ek), &
                                       [size(gs%stress, 2), size(gs%stress, 3)])
          gs%back(i, :, :) = reshape(real(rows(o(2) + 1:o(2) + size(gs%back(i, :, :)), e), ek), &
                                     [size(gs%back, 2), size(gs%back, 3)])
          gs%eps_p(i, :) = real(rows(o(3) + 1:o(3) + size(gs%eps_p, 2), e), ek)
          gs%hourglass(i, :) = real(rows(o(4) + 1:o(4) + hourglass_components, e), ek)
          gs%state(i, :, :) = reshape(real(rows(o(5) + 1:o(5) + size(gs%state(i, :, :)), e), ek), &
                                      [size(gs%state, 2), size(gs%state, 3)])
          if (size(gs%thickness) > 0) gs%thickness(i) = real(rows(size(rows, 1), e), ek)
        end do
      end associate
    end do
    es%e_internal = rows(o(4) + hourglass_components + 1, :)
    es%e_hourglass = rows(o(4) + hourglass_components + 2, :)
  end subroutine element_rows_unpack

  !> Where stress, back stress, plastic strain, hourglass and material state start in an element
  !> row of `width` (the energies follow the hourglass resultants).
  pure function row_offsets(width, max_state) result(o)
    integer, intent(in) :: width, max_state
    integer :: o(5), nip_max
    nip_max = (width - hourglass_components - 2) / (stress_components + 3 + 1 + max_state)
    o(1) = 0
    o(2) = stress_components * nip_max
    o(3) = o(2) + 3 * nip_max
    o(4) = o(3) + nip_max
    o(5) = o(4) + hourglass_components + 2
  end function row_offsets

end module element_state
