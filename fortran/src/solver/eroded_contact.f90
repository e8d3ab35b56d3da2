!> What erosion takes out of the contact (docs/theory.md, "Element erosion"): after each step's
!> element forces, the elements of this rank that have eroded since the last look and, once some
!> have, the nodes left without a live element, shared with every rank so the contact
!> (contact_erosion_marks) leaves out the same segments and slaves on any layout. A model whose
!> contact parts cannot erode, or without contact, calls nothing; one that can pays a scan of its
!> eroding groups' plastic strains and, on several ranks, one integer sum per step. A node's live
!> elements are counted through the element corners and the same exchange and fixed-order sum as
!> the forces (its elements may lie on several ranks).
module eroded_contact
  use mpi_f08, only: MPI_Allreduce, MPI_Allgather, MPI_Allgatherv, MPI_IN_PLACE, MPI_INTEGER, MPI_SUM
  use paradyn_kinds, only: wp
  use element_erosion, only: element_eroded
  use halo_exchange, only: exchange_corners
  use nodal_assembly, only: assemble_nodes
  use contact_erosion_marks, only: contact_erosion_found
  use solver_state, only: solver_t
  implicit none
  private
  public :: eroded_contact_setup, eroded_contact_step

contains

  !> Whether the contact must follow erosion: a contact and a deformable part whose material
  !> fails (the parts are the same on every rank).
  subroutine eroded_contact_setup(s)
    type(solver_t), intent(inout) :: s
    integer :: p
    s%contact_erodes = .false.
    if (.not. s%has_contact) return
    do p = 1, size(s%props)
      if (s%props(p)%failure_strain > 0.0_wp .and. .not. s%props(p)%rigid) s%contact_erodes = .true.
    end do
    if (.not. s%contact_erodes) return
    allocate (s%eroded_known(s%dom%n_elements), s%dead_known(s%dom%n_nodes), source=.false.)
  end subroutine eroded_contact_setup

  !> After the element forces: the newly eroded elements of every rank and the nodes they leave
  !> without a live element go to the contact for its next step (collective when any rank has
  !> one: every rank then takes part). A restart finds every element eroded before it as new.
  subroutine eroded_contact_step(s)
    type(solver_t), intent(inout) :: s
    integer, allocatable :: mine(:), dead(:)
    real(wp), allocatable :: corner(:, :), live(:, :)
    integer :: g, i, e, n_new, total
    n_new = 0
    do g = 1, s%dom%n_groups
      if (.not. can_erode(g)) cycle
      do i = 1, s%dom%group_count(g)
        if (newly_eroded(g, i)) n_new = n_new + 1
      end do
    end do
    total = n_new
    if (s%n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, total, 1, MPI_INTEGER, MPI_SUM, s%contact%comm)
    if (total == 0) return
    allocate (mine(n_new))
    n_new = 0
    do g = 1, s%dom%n_groups
      if (.not. can_erode(g)) cycle
      do i = 1, s%dom%group_count(g)
        if (.not. newly_eroded(g, i)) cycle
        e = s%dom%group_first(g) + i - 1
        s%eroded_known(e) = .true.
        n_new = n_new + 1
        mine(n_new) = s%dom%elements(e)
      end do
    end do
    ! each node's live elements (row 1) and elements (row 2), over every rank's corners
    allocate (corner(6, size(s%corner, 2)), source=0.0_wp)
    allocate (live(6, s%dom%n_nodes))
    do e = 1, s%dom%n_elements
      corner(1, 4 * e - 3:4 * e) = merge(0.0_wp, 1.0_wp, s%eroded_known(e))
      corner(2, 4 * e - 3:4 * e) = 1.0_wp
    end do
    call exchange_corners(s%dom, s%halo, corner)
    call assemble_nodes(s%dom%n_nodes, s%dom%assembly_start, s%dom%assembly_slot, corner, live)
    allocate (dead(size(s%contact%owned_local)))
    n_new = 0
    do i = 1, size(s%contact%owned_local)   ! this rank's own contact nodes (nodes%owned_member: their ids)
      e = s%contact%owned_local(i)
      if (s%dead_known(e) .or. live(1, e) > 0.0_wp .or. .not. (live(2, e) > 0.0_wp)) cycle
      n_new = n_new + 1
      dead(n_new) = s%contact%nodes%owned_member(i)
    end do
    s%dead_known = live(1, :) == 0.0_wp .and. live(2, :) > 0.0_wp
    call contact_erosion_found(s%contact%c, every_rank(s, mine), every_rank(s, dead(1:n_new)))

  contains

    !> Group g's part can erode (a deformable part with a failure strain).
    logical function can_erode(g)
      integer, intent(in) :: g
      can_erode = s%props(s%dom%group_part(g))%failure_strain > 0.0_wp .and. .not. s%props(s%dom%group_part(g))%rigid
    end function can_erode

    !> Element i of group g has eroded and the contact does not know it yet.
    logical function newly_eroded(g, i)
      integer, intent(in) :: g, i
      associate (props => s%props(s%dom%group_part(g)))
        newly_eroded = .not. s%eroded_known(s%dom%group_first(g) + i - 1)
        if (newly_eroded) newly_eroded = element_eroded(s%elements%groups(g)%eps_p(i, :), props%failure_strain, &
                                                        props%integration_points, props%failure_layers)
      end associate
    end function newly_eroded

  end subroutine eroded_contact_step

  !> Every rank's values, in rank order (this rank's alone on one rank).
  function every_rank(s, mine) result(all)
    type(solver_t), intent(in) :: s
    integer, intent(in) :: mine(:)
    integer, allocatable :: all(:), counts(:), displs(:)
    integer :: r
    if (s%n_ranks == 1) then
      all = mine
      return
    end if
    allocate (counts(s%n_ranks), displs(s%n_ranks))
    call MPI_Allgather(size(mine), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, s%contact%comm)
    displs(1) = 0
    do r = 2, s%n_ranks
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    allocate (all(sum(counts)))
    call MPI_Allgatherv(mine, size(mine), MPI_INTEGER, all, counts, displs, MPI_INTEGER, s%contact%comm)
  end function every_rank

end module eroded_contact
