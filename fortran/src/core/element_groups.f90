!> How elements are batched for the kernels: groups of one part of at most group_size elements,
!> so the element and material loops vectorise across a group.
module element_groups
  implicit none
  private
  public :: group_size

  integer, parameter :: group_size = 64   !< elements per kernel call (one part per group)
end module element_groups
