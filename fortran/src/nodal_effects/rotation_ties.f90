!> Rotation ties (docs/theory.md, "Rotation ties"): a node's angular velocity held to the weighted
!> mean of four master nodes' (a shell edge tied to a surface turns with it, LS-DYNA
!> *CONTACT_TIED_SHELL_EDGE_TO_SURFACE). After the velocity update each tie's constraint
!> w_s = sum_I N_I w_I is met by an angular impulse p on the slave and -N_I p on its masters,
!> p = (sum_I N_I w_I - w_s) / (1 / I_s + sum_I N_I^2 / I_I), I the nodes' rotary inertias (a
!> fixed rotation: 1 / I = 0, it takes no impulse): the angular momentum about every point is kept
!> where no rotation is fixed (the impulses sum to zero and act at the nodes as couples). Ties that share masters are met together by Gauss-Seidel sweeps in the ties'
!> order, a fixed number, so the answer does not depend on anything but the deck. Pure: the
!> plumbing (rotation_tie_effect) gathers the nodes' values over the ranks.
module rotation_ties
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: tie_rotations, tie_sweeps

  !> Gauss-Seidel sweeps per step: the constraints' residual falls by about the masters' share of
  !> the inertia per sweep (below 1e-12 of the velocities for shell meshes after this many)
  integer, parameter :: tie_sweeps = 30

contains

  !> The angular velocities w(3, nodes) of the tied nodes after the impulses that hold each tie
  !> k: slave(k)'s w to sum_I weight(I, k) w(:, masters(I, k)) (indices into w), component by
  !> component; mobility(c, n): 1 / the rotary inertia of node n about axis c, 0 where that
  !> rotation is fixed (a held dof takes no impulse: infinite inertia). work: what the impulses do
  !> (the change of the rotational kinetic energy, <= 0).
  pure subroutine tie_rotations(slave, masters, weight, mobility, w, work)
    integer, intent(in) :: slave(:), masters(:, :)
    real(wp), intent(in) :: weight(:, :), mobility(:, :)
    real(wp), intent(inout) :: w(:, :)
    real(wp), intent(out) :: work
    real(wp) :: before(3, size(w, 2)), target(3), p(3), compliance(3)
    integer :: sweep, k, i
    before = w
    do sweep = 1, tie_sweeps
      do k = 1, size(slave)
        target = matmul(w(:, masters(:, k)), weight(:, k))
        compliance = mobility(:, slave(k))
        do i = 1, 4
          compliance = compliance + weight(i, k)**2 * mobility(:, masters(i, k))
        end do
        p = 0.0_wp
        where (compliance > 0.0_wp) p = (target - w(:, slave(k))) / compliance
        w(:, slave(k)) = w(:, slave(k)) + p * mobility(:, slave(k))
        do i = 1, 4
          w(:, masters(i, k)) = w(:, masters(i, k)) - weight(i, k) * p * mobility(:, masters(i, k))
        end do
      end do
    end do
    work = 0.0_wp
    do k = 1, size(w, 2)
      do i = 1, 3
        if (mobility(i, k) > 0.0_wp) work = work + 0.5_wp * (w(i, k)**2 - before(i, k)**2) / mobility(i, k)
      end do
    end do
  end subroutine tie_rotations

end module rotation_ties
