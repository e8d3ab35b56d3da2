!> Tied contact (schema name "tied"; the penalty form of LS-DYNA's
!> *CONTACT_TIED_NODES_TO_SURFACE_OFFSET): the definition's first part is slave, its second master,
!> in one pass every cycle. At the start (the deck's positions) each slave node within the tie reach
!> of a master segment, (t_slave + t_master) / 2 plus tie_slack of it (round-off in stacked meshes),
!> is tied to its closest point there: the segment (its global element, the lowest among equally
!> near ones), the point's (xi, eta) and the node's offset from the point in the segment's frame at
!> it (tangent along xi, its normal in the plane, the normal), all kept for the run. Every step a
!> penalty spring pulls the node to the point's current place plus that offset, in every direction
!> (no separation, no sliding), and the reaction goes to the segment's four nodes by the shape
!> functions; the spring is the contact's own (contact_penalty's stiffness of the segment, capped
!> at the stable fraction of m / dt^2 by the local search). Nodes out of reach stay free. The ties
!> come from the deck's positions, so a restart ties the same; the start-up checks skip tied
!> definitions (trait "tied": they start inside the reach on purpose).
!>
!> The pass is bound (contact_pass: the trait tied): the local search (contact_stages) takes each
!> slave's segment from its binding, not from a search, and its force from the law contact_laws
!> names for this kind (tied_force); the global search, the records and their ordered sum are those
!> of every pass, so the forces are the same on any layout. One rank and the replicated scheme tie
!> every slave here (make_passes sees the whole deck); local contact binds each rank's own slaves
!> against the master elements near them (contact_local_setup, through contact_laws' bind_slaves).
module tied_contact
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use vector_algebra, only: cross
  use contact_pass, only: contact_pass_t, pass_between_parts
  use contact_kind, only: contact_kind_t
  use contact_surfaces, only: part_nodes
  use segment_projection, only: closest_point_on_segment, segment_shape_functions
  use surface_overlap, only: bin_elements, cell_of, index_of
  implicit none
  private
  public :: tied_t, tie_slaves, tie_reach, tied_force, segment_frame

  !> A slave is tied within (1 + tie_slack) (t_slave + t_master) / 2 of a segment: shells stacked
  !> at exactly their half thicknesses tie whatever the round-off of their coordinates.
  real(wp), parameter :: tie_slack = 0.01_wp

  type, extends(contact_kind_t) :: tied_t
  contains
    procedure :: pass_count => tied_pass_count
    procedure :: make_passes => tied_passes
  end type tied_t

contains

  pure integer function tied_pass_count(self) result(n)
    class(tied_t), intent(in) :: self
    n = 1
  end function tied_pass_count

  !> The pass of the first part's nodes against the second's segments, every slave tied (a deck
  !> without its mesh, as local contact gives, ties none: contact_local_setup ties each rank's own).
  subroutine tied_passes(self, deck, definition, contact_id, n_contact, passes)
    class(tied_t), intent(in) :: self
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, contact_id(:), n_contact
    type(contact_pass_t), intent(inout) :: passes(:)
    integer, allocatable :: slave_nodes(:), slave_elements(:), master_nodes(:), elements(:)
    associate (pass => passes(1))
    call pass_between_parts(deck, definition, deck%contact_pairs(1, definition), deck%contact_pairs(2, definition), &
                            contact_id, pass)
    pass%every_cycle = .true.
    call part_nodes(deck, pass%slave_part, slave_nodes, slave_elements)
    call part_nodes(deck, pass%master_part, master_nodes, elements)
    call tie_slaves(deck%coordinates, slave_nodes, deck%connectivity(:, elements), elements, tie_reach(pass), &
                    pass%bound_element, pass%bound_data)
    end associate
  end subroutine tied_passes

  !> How far from a segment a slave of the pass is tied.
  pure real(wp) function tie_reach(pass)
    type(contact_pass_t), intent(in) :: pass
    tie_reach = (1.0_wp + tie_slack) * 0.5_wp * (pass%t_slave + pass%t_master)
  end function tie_reach

  !> The ties of the nodes at x(:, slaves) to the elements (4, n: columns of x; ids ascending) within
  !> reach: tie_element(s) the id of the element whose closest point is nearest (the lowest id among
  !> equals; 0: none within reach), tie_point(:, s) the point's xi, eta and the node's offset in the
  !> element's frame there. A node never ties to an element of its own. Elements are binned in cells
  !> as large as the largest (surface_overlap), so the cost is linear in the nodes.
  subroutine tie_slaves(x, slaves, elements, ids, reach, tie_element, tie_point)
    real(wp), intent(in) :: x(:, :), reach
    integer, intent(in) :: slaves(:), elements(:, :), ids(:)
    integer, allocatable, intent(out) :: tie_element(:)
    real(wp), allocatable, intent(out) :: tie_point(:, :)
    real(wp) :: lower(3), cell, p(3), xi, eta, xc(3), normal(3), distance, best_distance, frame(3, 3)
    integer :: dims(3), s, i, j, l, f, e, best, lo(3), hi(3)
    integer, allocatable :: start(:), members(:)
    allocate (tie_element(size(slaves)), source=0)
    allocate (tie_point(5, size(slaves)), source=0.0_wp)
    if (size(slaves) == 0 .or. size(elements, 2) == 0) return
    call bin_elements(x, elements, lower, cell, dims, start, members)
    do s = 1, size(slaves)
      p = x(:, slaves(s))
      lo = cell_of(p - reach, lower, cell, dims)
      hi = cell_of(p + reach, lower, cell, dims)
      best = huge(1)
      best_distance = huge(1.0_wp)
      do l = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            do f = start(index_of(i, j, l, dims)), start(index_of(i, j, l, dims) + 1) - 1
              e = members(f)
              if (any(elements(:, e) == slaves(s))) cycle
              call closest_point_on_segment(x(:, elements(:, e)), p, xi, eta, xc, normal)
              distance = norm2(p - xc)
              if (distance > reach) cycle
              if (distance < best_distance .or. (distance == best_distance .and. e < best)) then
                best = e
                best_distance = distance
                tie_point(1:2, s) = [xi, eta]
                frame = segment_frame(x(:, elements(:, e)), xi, eta)
                tie_point(3:5, s) = matmul(p - xc, frame)
              end if
            end do
          end do
        end do
      end do
      if (best < huge(1)) tie_element(s) = ids(best)
    end do
  end subroutine tie_slaves

  !> The tie's spring on a slave at p, tied at tie (xi, eta, offset) to the segment xseg (3, 4), of
  !> stiffness k: f_slave = k (target - p), target the tied point plus the offset in the segment's
  !> current frame; master node I gets -N_I f_slave, so the forces sum to zero.
  pure subroutine tied_force(p, xseg, tie, k, f_slave, f_master)
    real(wp), intent(in) :: p(3), xseg(3, 4), tie(5), k
    real(wp), intent(out) :: f_slave(3), f_master(3, 4)
    real(wp) :: shape(4), target(3), frame(3, 3)
    integer :: i
    shape = segment_shape_functions(tie(1), tie(2))
    frame = segment_frame(xseg, tie(1), tie(2))
    target = matmul(xseg, shape) + matmul(frame, tie(3:5))
    f_slave = k * (target - p)
    do i = 1, 4
      f_master(:, i) = -shape(i) * f_slave
    end do
  end subroutine tied_force

  !> The orthonormal frame of the segment at (xi, eta), columns: the unit tangent along xi, the
  !> normal's cross product with it, the unit normal dx/dxi x dx/deta (of the diagonals where that
  !> vanishes, at a triangle's collapsed corner; a tangent along eta where the xi one does).
  pure function segment_frame(xseg, xi, eta) result(frame)
    real(wp), intent(in) :: xseg(3, 4), xi, eta
    real(wp) :: frame(3, 3), along_xi(3), along_eta(3), normal(3), tangent(3)
    along_xi = 0.25_wp * ((1.0_wp - eta) * (xseg(:, 2) - xseg(:, 1)) + (1.0_wp + eta) * (xseg(:, 3) - xseg(:, 4)))
    along_eta = 0.25_wp * ((1.0_wp - xi) * (xseg(:, 4) - xseg(:, 1)) + (1.0_wp + xi) * (xseg(:, 3) - xseg(:, 2)))
    normal = cross(along_xi, along_eta)
    if (.not. (norm2(normal) > 1.0e-12_wp * (dot_product(along_xi, along_xi) + dot_product(along_eta, along_eta)))) &
      normal = cross(xseg(:, 3) - xseg(:, 1), xseg(:, 4) - xseg(:, 2))
    normal = normal / norm2(normal)
    tangent = along_xi - dot_product(along_xi, normal) * normal
    if (.not. (norm2(tangent) > 1.0e-6_wp * norm2(along_eta))) &
      tangent = cross(along_eta - dot_product(along_eta, normal) * normal, normal)
    tangent = tangent / norm2(tangent)
    frame(:, 1) = tangent
    frame(:, 2) = cross(normal, tangent)
    frame(:, 3) = normal
  end function segment_frame

end module tied_contact
