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
  public :: material_from_name, material_name_of_code, material_names

  !> Schema names of the members, in the order of their deck codes (/materials/model = 1, 2, ...)
  character(len=*), parameter :: material_names(2) = [character(len=13) :: 'elastic', 'j2_plasticity']

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

  !> The schema name of a /materials/model code, '' for an unknown code.
  pure function material_name_of_code(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    name = ''
    if (code >= 1 .and. code <= size(material_names)) name = trim(material_names(code))
  end function material_name_of_code

end module material_factory
