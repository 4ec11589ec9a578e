"""The learned layout model: geometry encoder, layout predictor, mixture-of-logistics head."""
