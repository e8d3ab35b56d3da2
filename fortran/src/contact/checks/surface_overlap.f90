!> Whether the mid-surfaces of two parts cross at the start (issue 17): an element side of one
!> part that pierces an element of the other. Contact then never engages (the nodes are past the
!> surface they should meet, and farther than the search looks), so such a deck is refused before
!> the run. Elements of the second part are binned in a uniform grid of cells about as large as
!> its largest element, so each side is tested against the few elements near it: linear in the
!> elements. No MPI, no I/O.
module surface_overlap
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: first_crossing, bin_elements, cell_of, index_of

contains

  !> The first element side of elements_a (4, n) that pierces an element of elements_b, as the
  !> element of a, the element of b (the first in their order that the side pierces) and the
  !> point; element_a = 0 when none does. Sides that only touch an element (a shared node or edge,
  !> within round-off) do not count. The answer does not depend on the grid's cells, so a rank
  !> holding only the elements of b near its elements of a, in the same order, finds the same.
  subroutine first_crossing(x, elements_a, elements_b, element_a, element_b, point)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: elements_a(:, :), elements_b(:, :)
    integer, intent(out) :: element_a, element_b
    real(wp), intent(out) :: point(3)
    real(wp) :: lower(3), cell, hit(3)
    integer :: dims(3), e, k, i, j, l, lo(3), hi(3), f
    integer, allocatable :: start(:), members(:)
    element_a = 0
    element_b = 0
    point = 0.0_wp
    if (size(elements_a, 2) == 0 .or. size(elements_b, 2) == 0) return
    call bin_elements(x, elements_b, lower, cell, dims, start, members)
    do e = 1, size(elements_a, 2)
      do k = 1, 4
        associate (p => x(:, elements_a(k, e)), q => x(:, elements_a(modulo(k, 4) + 1, e)))
          lo = cell_of(min(p, q), lower, cell, dims)
          hi = cell_of(max(p, q), lower, cell, dims)
          do l = lo(3), hi(3)
            do j = lo(2), hi(2)
              do i = lo(1), hi(1)
                do f = start(index_of(i, j, l, dims)), start(index_of(i, j, l, dims) + 1) - 1
                  if (element_b > 0 .and. members(f) >= element_b) cycle
                  if (side_pierces(p, q, x(:, elements_b(:, members(f))), hit)) then
                    element_a = e
                    element_b = members(f)
                    point = hit
                  end if
                end do
              end do
            end do
          end do
        end associate
        if (element_a > 0) return
      end do
    end do
  end subroutine first_crossing

  !> Each element of b in every cell its bounding box overlaps (cells of size the largest element
  !> extent, or 1/256 of the model's largest extent if that is larger), as lists start(c) .. start(c + 1) - 1 of members.
  subroutine bin_elements(x, elements, lower, cell, dims, start, members)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: elements(:, :)
    real(wp), intent(out) :: lower(3), cell
    integer, intent(out) :: dims(3)
    integer, allocatable, intent(out) :: start(:), members(:)
    real(wp) :: upper(3), box_lo(3, size(elements, 2)), box_hi(3, size(elements, 2))
    integer, allocatable :: fill(:)
    integer :: e, i, j, l, lo(3), hi(3), pass, c
    do e = 1, size(elements, 2)
      box_lo(:, e) = minval(x(:, elements(:, e)), dim=2)
      box_hi(:, e) = maxval(x(:, elements(:, e)), dim=2)
    end do
    lower = minval(box_lo, dim=2)
    upper = maxval(box_hi, dim=2)
    cell = max(maxval(box_hi - box_lo), 1.0e-12_wp * max(maxval(upper - lower), 1.0_wp))
    ! at most 256 cells a side: a longer model gets larger cells (clamping the indices instead would
    ! pile every element past the 256th cell into the last one, and the search would turn quadratic)
    cell = max(cell, maxval(upper - lower) / 256.0_wp)
    dims = max(1, min(256, ceiling((upper - lower) / cell)))
    allocate (start(product(dims) + 1), fill(product(dims)), source=0)
    do pass = 1, 2   ! count, then place
      fill = 0
      do e = 1, size(elements, 2)
        lo = cell_of(box_lo(:, e), lower, cell, dims)
        hi = cell_of(box_hi(:, e), lower, cell, dims)
        do l = lo(3), hi(3)
          do j = lo(2), hi(2)
            do i = lo(1), hi(1)
              c = index_of(i, j, l, dims)
              if (pass == 2) members(start(c) + fill(c)) = e
              fill(c) = fill(c) + 1
            end do
          end do
        end do
      end do
      if (pass == 1) then
        start(1) = 1
        do c = 1, product(dims)
          start(c + 1) = start(c) + fill(c)
        end do
        allocate (members(start(product(dims) + 1) - 1))
      end if
    end do
  end subroutine bin_elements

  pure function cell_of(p, lower, cell, dims) result(ijk)
    real(wp), intent(in) :: p(3), lower(3), cell
    integer, intent(in) :: dims(3)
    integer :: ijk(3)
    ijk = min(dims, max(1, 1 + floor((p - lower) / cell)))
  end function cell_of

  pure integer function index_of(i, j, l, dims)
    integer, intent(in) :: i, j, l, dims(3)
    index_of = i + dims(1) * ((j - 1) + dims(2) * (l - 1))
  end function index_of

  !> Whether the segment p-q passes through the quadrilateral y (its two triangles 1-2-3 and
  !> 1-3-4) strictly inside, away from its ends and from the triangles' edges by a relative
  !> 1e-9, so that touching at a shared node or edge is not a crossing; where, in point.
  logical function side_pierces(p, q, y, point) result(pierces)
    real(wp), intent(in) :: p(3), q(3), y(3, 4)
    real(wp), intent(inout) :: point(3)
    pierces = through_triangle(p, q, y(:, 1), y(:, 2), y(:, 3), point) .or. &
              through_triangle(p, q, y(:, 1), y(:, 3), y(:, 4), point)
  end function side_pierces

  logical function through_triangle(p, q, a, b, c, point) result(through)
    real(wp), intent(in) :: p(3), q(3), a(3), b(3), c(3)
    real(wp), intent(inout) :: point(3)
    real(wp), parameter :: margin = 1.0e-9_wp
    real(wp) :: n(3), dp, dq, t, hit(3), u, v, w, area
    through = .false.
    n = cross(b - a, c - a)
    area = dot_product(n, n)
    if (area <= 0.0_wp) return
    dp = dot_product(n, p - a)
    dq = dot_product(n, q - a)
    if (dp * dq >= 0.0_wp) return   ! both ends on one side (or one end in the plane: a touch)
    t = dp / (dp - dq)
    if (t <= margin .or. t >= 1.0_wp - margin) return
    hit = p + t * (q - p)
    u = dot_product(cross(c - b, hit - b), n) / area   ! barycentric weights of a, b, c
    v = dot_product(cross(a - c, hit - c), n) / area
    w = 1.0_wp - u - v
    through = min(u, v, w) > margin
    if (through) point = hit
  end function through_triangle

end module surface_overlap
