!> Slave nodes that start inside the contact thickness of the surface they should meet (issue 15):
!> how deep, where, and the push that takes each out, by the same geometry as the penalty force
!> (contact_search's penalty_force with unit stiffness: its force is the depth along the push).
!> Every contact definition is checked before the run and reported; the scene chooses what is
!> done: the nodes are moved onto the surface (the default: initial displacements the solver
!> adds), or their overlap is kept as their gap (contact_pass). Master elements are binned as in surface_overlap, so the check is linear in
!> the nodes. On the global deck, the same on every rank; no MPI.
module initial_penetration
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use contact_search, only: penalty_force
  use surface_overlap, only: bin_elements, cell_of, index_of
  use paradyn_schema, only: initial_penetration_move, contact_kind_single_surface
  use contact_surfaces, only: part_nodes, contact_thickness
  implicit none
  private
  public :: slave_penetrations, resolve_initial_penetrations

contains

  !> depth(s): the deepest penetration of node slaves(s) past the thickened surfaces of elements
  !> (4, n) at the positions x, 0 where none; push(:, s) the move that takes it out.
  subroutine slave_penetrations(x, slaves, elements, t_slave, t_master, depth, push)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: slaves(:), elements(:, :)
    real(wp), intent(in) :: t_slave, t_master
    real(wp), intent(out) :: depth(:), push(:, :)
    real(wp) :: lower(3), cell, reach, p(3), f_slave(3), f_master(3, 4), penetration
    integer :: dims(3), s, i, j, l, f, e, lo(3), hi(3)
    integer, allocatable :: start(:), members(:)
    logical :: touching
    depth = 0.0_wp
    push = 0.0_wp
    if (size(slaves) == 0 .or. size(elements, 2) == 0) return
    call bin_elements(x, elements, lower, cell, dims, start, members)
    reach = 0.5_wp * (t_slave + t_master)
    do s = 1, size(slaves)
      p = x(:, slaves(s))
      lo = cell_of(p - reach, lower, cell, dims)
      hi = cell_of(p + reach, lower, cell, dims)
      do l = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            do f = start(index_of(i, j, l, dims)), start(index_of(i, j, l, dims) + 1) - 1
              e = members(f)
              if (any(elements(:, e) == slaves(s))) cycle   ! a node never contacts its own elements
              call penalty_force(p, t_slave, x(:, elements(:, e)), t_master, 1.0_wp, f_slave, f_master, &
                                 penetration, touching, rounded_edges=.true.)
              if (touching .and. penetration > depth(s)) then
                depth(s) = penetration
                push(:, s) = f_slave
              end if
            end do
          end do
        end do
      end do
    end do
  end subroutine slave_penetrations

  !> Checks every contact definition, both ways, at the deck's positions; where a definition asks
  !> for it, the penetrating slave nodes get the moves (3, n_nodes) that put them onto the
  !> surface (then the check runs again on the moved positions: moving one side's nodes may leave
  !> the other's inside). Each definition with penetrations is reported on `unit` when speak (rank
  !> 0). The deck keeps its coordinates: the solver adds the moves to the start positions, so they
  !> show as initial displacements.
  subroutine resolve_initial_penetrations(deck, speak, unit, moves)
    type(deck_t), intent(in) :: deck
    logical, intent(in) :: speak
    integer, intent(in) :: unit
    real(wp), allocatable, intent(out) :: moves(:, :)
    real(wp), allocatable :: x(:, :)
    integer :: k
    x = deck%coordinates
    do k = 1, deck%n_contacts
      if (deck%contact_initial_penetration(k) == initial_penetration_move) then
        call check_definition(deck, x, k, .true., speak, unit, 'moved onto the surface')
        call check_definition(deck, x, k, .false., speak, unit, 'still inside after the move')
      else
        call check_definition(deck, x, k, .false., speak, unit, 'kept as the initial gap')
      end if
    end do
    moves = x - deck%coordinates
  end subroutine resolve_initial_penetrations

  !> Both passes of definition k at the positions x: report the penetrating slave nodes; move
  !> them in x when asked.
  subroutine check_definition(deck, x, k, move, speak, unit, what)
    type(deck_t), intent(in) :: deck
    real(wp), intent(inout) :: x(:, :)
    integer, intent(in) :: k, unit
    logical, intent(in) :: move, speak
    character(len=*), intent(in) :: what
    integer, allocatable :: slaves(:), elements(:), masters(:), master_elements(:)
    real(wp), allocatable :: depth(:), push(:, :)
    integer :: side, slave_part, master_part, deepest
    real(wp) :: reach, t_slave, t_master
    do side = 1, 2
      slave_part = deck%contact_pairs(side, k)
      master_part = deck%contact_pairs(3 - side, k)
      ! a single-surface definition names its part twice: one pass
      if (side == 2 .and. deck%contact_kind(k) == contact_kind_single_surface) exit
      call part_nodes(deck, slave_part, slaves, elements)
      call part_nodes(deck, master_part, masters, master_elements)
      t_slave = contact_thickness(deck, k, slave_part)
      t_master = contact_thickness(deck, k, master_part)
      allocate (depth(size(slaves)), push(3, size(slaves)))
      call slave_penetrations(x, slaves, deck%connectivity(:, master_elements), t_slave, t_master, depth, push)
      if (any(depth > 0.0_wp)) then
        deepest = maxloc(depth, 1)
        reach = 0.5_wp * (t_slave + t_master)
        if (speak) write (unit, '(a,i0,a,i0,a,i0,a,i0,a,es10.3,a,f5.3,a,i0,a,3es11.3,a)') &
          'paradyn-engine: warning: initial penetration in /contact/pairs[', k - 1, ']: ', count(depth > 0.0_wp), &
          ' nodes of part ', slave_part - 1, ' inside the contact thickness of part ', master_part - 1, &
          ', deepest', depth(deepest), ' m (', depth(deepest) / reach, ' of the reach (t_slave + t_master)/2) '// &
          'at node ', slaves(deepest) - 1, ' near', x(:, slaves(deepest)), '; '//what
        if (move) x(:, slaves) = x(:, slaves) + push
      end if
      deallocate (depth, push)
    end do
  end subroutine check_definition

end module initial_penetration
