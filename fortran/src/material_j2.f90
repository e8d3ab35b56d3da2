!> Material laws at one integration point, in plane stress.
!>
!> J2 plasticity with linear combined isotropic/kinematic hardening and a radial return that
!> satisfies the plane-stress condition exactly (Simo & Taylor 1986; Simo & Hughes,
!> Computational Inelasticity, 1998, sec. 3.4). Stress vectors are (sxx, syy, sxy).
module material_j2
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: elastic_plane_stress_update, j2_plane_stress_update, von_mises_plane_stress

contains

  !> Linear elastic plane-stress increment: stress += C * dstrain (dstrain has engineering shear).
  pure subroutine elastic_plane_stress_update(stress, dstrain, young, poisson)
    real(wp), intent(inout) :: stress(3)
    real(wp), intent(in) :: dstrain(3), young, poisson
    real(wp) :: c
    c = young / (1.0_wp - poisson**2)
    stress(1) = stress(1) + c * (dstrain(1) + poisson * dstrain(2))
    stress(2) = stress(2) + c * (dstrain(2) + poisson * dstrain(1))
    stress(3) = stress(3) + c * 0.5_wp * (1.0_wp - poisson) * dstrain(3)
  end subroutine elastic_plane_stress_update

  pure real(wp) function von_mises_plane_stress(s) result(vm)
    real(wp), intent(in) :: s(3)
    vm = sqrt(max(s(1)**2 - s(1) * s(2) + s(2)**2 + 3.0_wp * s(3)**2, 0.0_wp))
  end function von_mises_plane_stress

  !> Plane-stress J2 return mapping with combined hardening.
  !>
  !> Plastic modulus H = E Et / (E - Et); isotropic part beta*H, kinematic part (1-beta)*H.
  !> Flow eps_p' = dgamma P xi, back stress alpha' = (2/3) h_kin dgamma xi, xi = sigma - alpha.
  !> The return is solved in the eigenbasis of the plane-stress projector P, where the update is
  !> diagonal, for the consistency parameter dgamma by safeguarded Newton iteration.
  pure subroutine j2_plane_stress_update(stress, back, eps_p, dstrain, young, poisson, &
                                         yield0, tangent, beta)
    real(wp), intent(inout) :: stress(3), back(3), eps_p
    real(wp), intent(in) :: dstrain(3), young, poisson, yield0, tangent, beta
    real(wp) :: h, h_iso, h_kin, shear, c1, c2, a1t, a2t, a3t, psi_trial, sy
    real(wp) :: dgamma, lo, hi, f, df, psi, s1, s2, a1, a2, a3
    real(wp) :: xi(3)
    integer :: iter

    call elastic_plane_stress_update(stress, dstrain, young, poisson)
    xi = stress - back
    h = young * tangent / (young - tangent)
    h_iso = beta * h
    h_kin = (1.0_wp - beta) * h
    sy = yield0 + h_iso * eps_p
    if (von_mises_plane_stress(xi) <= sy) return

    shear = young / (2.0_wp * (1.0_wp + poisson))
    c1 = young / (3.0_wp * (1.0_wp - poisson)) + 2.0_wp * h_kin / 3.0_wp
    c2 = 2.0_wp * shear + 2.0_wp * h_kin / 3.0_wp
    a1t = (xi(1) + xi(2)) / sqrt(2.0_wp)
    a2t = (xi(2) - xi(1)) / sqrt(2.0_wp)
    a3t = xi(3)
    psi_trial = a1t**2 / 3.0_wp + a2t**2 + 2.0_wp * a3t**2

    ! f(dgamma) = psi/2 - sy^2/3 decreases monotonically from f(0) > 0.
    lo = 0.0_wp
    hi = 1.0_wp / c2
    do iter = 1, 200
      if (yield_function(hi) < 0.0_wp) exit
      hi = 2.0_wp * hi
    end do
    dgamma = 0.0_wp
    do iter = 1, 100
      call evaluate(dgamma, f, df)
      if (f > 0.0_wp) then
        lo = dgamma
      else
        hi = dgamma
      end if
      if (abs(f) <= 1.0e-13_wp * yield0**2) exit
      dgamma = dgamma - f / df
      if (dgamma <= lo .or. dgamma >= hi .or. df >= 0.0_wp) dgamma = 0.5_wp * (lo + hi)
      if (hi - lo <= 1.0e-15_wp * hi) exit
    end do

    s1 = 1.0_wp / (1.0_wp + dgamma * c1)
    s2 = 1.0_wp / (1.0_wp + dgamma * c2)
    a1 = a1t * s1
    a2 = a2t * s2
    a3 = a3t * s2
    psi = a1**2 / 3.0_wp + a2**2 + 2.0_wp * a3**2
    xi(1) = (a1 - a2) / sqrt(2.0_wp)
    xi(2) = (a1 + a2) / sqrt(2.0_wp)
    xi(3) = a3
    ! back stress moves along the relative stress, (2/3) h_kin dgamma xi (Simo & Hughes, Box 3.3):
    ! under uniaxial stress it stays uniaxial and the plastic modulus is h_kin
    back = back + 2.0_wp / 3.0_wp * h_kin * dgamma * xi
    eps_p = eps_p + dgamma * sqrt(2.0_wp * psi / 3.0_wp)
    stress = xi + back

  contains

    pure real(wp) function yield_function(dg) result(fv)
      real(wp), intent(in) :: dg
      real(wp) :: d
      call evaluate(dg, fv, d)
    end function yield_function

    pure subroutine evaluate(dg, fv, dfv)
      real(wp), intent(in) :: dg
      real(wp), intent(out) :: fv, dfv
      real(wp) :: t1, t2, p, dp, root, de, dde, sy_new
      t1 = 1.0_wp / (1.0_wp + dg * c1)
      t2 = 1.0_wp / (1.0_wp + dg * c2)
      p = (a1t * t1)**2 / 3.0_wp + (a2t**2 + 2.0_wp * a3t**2) * t2**2
      dp = -2.0_wp * ((a1t * t1)**2 / 3.0_wp * c1 * t1 + (a2t**2 + 2.0_wp * a3t**2) * t2**2 * c2 * t2)
      root = sqrt(max(2.0_wp * p / 3.0_wp, 0.0_wp))
      de = dg * root
      dde = root + merge(dg * dp / (3.0_wp * root), 0.0_wp, root > 0.0_wp)
      sy_new = yield0 + h_iso * (eps_p + de)
      fv = 0.5_wp * p - sy_new**2 / 3.0_wp
      dfv = 0.5_wp * dp - 2.0_wp / 3.0_wp * sy_new * h_iso * dde
    end subroutine evaluate

  end subroutine j2_plane_stress_update

end module material_j2
