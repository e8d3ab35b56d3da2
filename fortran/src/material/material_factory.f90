!> Makes a member of the material family from its schema name and the deck's parameters of one
!> material (the parameters a member does not use are ignored). Adding a member: its module, a
!> case here, and its name in the schema.
module material_factory
  use paradyn_kinds, only: wp
  use material_model, only: material_t
  use elastic_material, only: elastic_material_t
  use j2_material, only: j2_material_t
  implicit none
  private
  public :: material_from_name

contains

  !> The member named name; not allocated for an unknown name.
  subroutine material_from_name(name, young, poisson, yield_stress, tangent_modulus, hardening_mixing, &
                                     material)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: young, poisson, yield_stress, tangent_modulus, hardening_mixing
    class(material_t), allocatable, intent(out) :: material
    select case (name)
    case ('elastic')
      allocate (material, source=elastic_material_t(young=young, poisson=poisson))
    case ('j2_plasticity')
      allocate (material, source=j2_material_t(young=young, poisson=poisson, yield_stress=yield_stress, &
                                               tangent_modulus=tangent_modulus, hardening_mixing=hardening_mixing))
    end select
  end subroutine material_from_name

end module material_factory
