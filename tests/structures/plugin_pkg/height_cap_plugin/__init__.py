"""A structure plug-in, as an installed package would ship one: a design stands while its model
is no taller than a cap (a planning rule rather than mechanics, which is the point: any measure
that is zero exactly when the design is acceptable can drive the search)."""

from shapegen.structures import Assessment, Design, Reserve, Structure, StructureArgument
from shapegen.structures.registry import register_structure


@register_structure
class HeightCap(Structure):
    name = "height_cap"
    description = "the model is no taller than a cap"
    measure_name = "(h/h_max - 1)²"
    arguments = {"max_height": StructureArgument("tallest allowed, m")}

    def assess(self, design: Design, *, margin: Reserve | float = 0.0) -> Assessment:
        margin = Reserve.of(margin)
        cap = (1.0 - margin) * self.checked_arguments(design.arguments)["max_height"]
        height = max(float(b.vertices[:, 1].max()) for b in design.model.blocks)
        stands = height <= cap
        return Assessment(
            structure=self.name,
            stands=stands,
            measure=0.0 if stands else (height / cap - 1.0) ** 2,
            status="optimal",
            section={"height": height, "max_height": cap},
            margin=margin,
        )
