!> Makes a member of the material family for one material of the deck, by its schema name (the
!> deck's fields: deck_fields, generated from the schema, so a member's new parameter is a dataset
!> in schema/deck.toml and nothing more here). Adding a member: its module, a case here, and its
!> name in the schema's enum material_model (with its traits, e.g. plastic).
module material_factory
  use paradyn_schema, only: enum_name, enum_material_model
  use deck_fields, only: deck_fields_t
  use material_model, only: material_t, max_state_words
  use elastic_material, only: elastic_material_t
  use j2_material, only: j2_material_t
  use j2_rate_material, only: j2_rate_material_t
  implicit none
  private
  public :: material_from_deck

contains

  !> The member for material m of deck; not allocated for an unknown name or a member that
  !> would keep more state per point than the element state holds (max_state_words).
  subroutine material_from_deck(deck, m, material)
    class(deck_fields_t), intent(in) :: deck
    integer, intent(in) :: m
    class(material_t), allocatable, intent(out) :: material
    select case (enum_name(enum_material_model, deck%material_model(m)))
    case ('elastic', 'rigid')   ! a rigid part has no stress: its elastic constants set the contact stiffness
      allocate (material, source=elastic_material_t(young=deck%young(m), poisson=deck%poisson(m)))
    case ('j2_plasticity')
      allocate (material, source=j2_material_t(young=deck%young(m), poisson=deck%poisson(m), &
                                               yield_stress=deck%yield_stress(m), &
                                               tangent_modulus=deck%tangent_modulus(m), &
                                               hardening_mixing=deck%hardening_mixing(m)))
    case ('j2_rate')
      allocate (material, source=j2_rate_material_t(young=deck%young(m), poisson=deck%poisson(m), &
                                                    yield_stress=deck%yield_stress(m), &
                                                    tangent_modulus=deck%tangent_modulus(m), &
                                                    hardening_mixing=deck%hardening_mixing(m), &
                                                    rate_c=deck%rate_c(m), rate_p=deck%rate_p(m)))
    end select
    if (allocated(material)) then
      if (material%state_width() > max_state_words) deallocate (material)
    end if
  end subroutine material_from_deck

end module material_factory
